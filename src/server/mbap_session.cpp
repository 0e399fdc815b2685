#include "server/mbap_session.hpp"

#include <algorithm>
#include <cstring>

#include "protocol/adu_writer.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::server {

namespace {

// Busy answers a connection may queue past its outstanding limit before the reader stops
// reading (and TCP flow control slows the client down).
constexpr std::size_t kBusySlack = 16;
// Room for the answers queued outside the reader's checks: a timed-out partial frame's
// exception and a close marker.
constexpr std::size_t kReserveSlots = 2;

std::size_t outstanding_limit(const MbapSessionLimits& limits) {
    return std::max<std::size_t>(1, limits.max_outstanding);
}

protocol::MbapHeader answer_header(const protocol::MbapHeader& request) {
    return {request.transaction_id, 0, 0, request.unit_id};
}

// Lends the handler a way to answer later; only a deferring handler asks for it.
class SessionDeferral final : public device::Deferral {
  public:
    SessionDeferral(MbapSession::Host& host, std::uint32_t ticket,
                    const protocol::MbapHeader& request)
        : host_(host), ticket_(ticket), request_(request) {}
    device::DeferredDone take() override { return host_.route_deferred(ticket_, request_); }

  private:
    MbapSession::Host& host_;
    std::uint32_t ticket_;
    const protocol::MbapHeader& request_;
};

}  // namespace

MbapSession::MbapSession(device::RequestHandler& handler, const MbapSessionLimits& limits,
                         ServerStats& stats, Host& host, Clock::time_point now)
    : handler_(handler),
      limits_(limits),
      stats_(stats),
      host_(host),
      replies_(outstanding_limit(limits) + kBusySlack + kReserveSlots),
      last_activity_(now) {}

void MbapSession::received(std::size_t count, Clock::time_point now) {
    input_begin_ = 0;
    input_end_ = std::min(count, input_.size());
    process_input(now);
}

void MbapSession::receive(std::span<const std::uint8_t> bytes, Clock::time_point now) {
    const auto count = std::min(bytes.size(), input_.size());
    std::copy_n(bytes.begin(), count, input_.begin());
    received(count, now);
}

void MbapSession::end_of_input(Clock::time_point now) {
    // An unfinished frame's missing bytes can no longer arrive: it is answered now, and the
    // requests recovered after an overlong frame are framed before the connection closes.
    eof_ = true;
    if (has_partial()) on_partial_timeout(now);
    process_input(now);
}

void MbapSession::finish_input(Clock::time_point now) {
    if (has_partial()) on_partial_timeout(now);
    stopped_ = true;
}

void MbapSession::process_input(Clock::time_point now) {
    while (input_begin_ < input_end_ && !stopped_) {
        const auto input =
            std::span<const std::uint8_t>(input_.data() + input_begin_, input_end_ - input_begin_);
        if (unfinished_.overlong()) {
            input_begin_ = input_end_;
            if (unfinished_.skip(input)) {
                partial_deadline_ = now + limits_.partial_frame_timeout;
            } else {
                ServerStats::bump(stats_.closed_bad_frame);
                close_after_answers(now);
            }
            continue;
        }
        // The owner sends what is ready; sent() comes back here once the client took some.
        if (must_pause(now)) return;
        std::size_t consumed = 0;
        const auto event = framer_.feed(input, consumed);
        input_begin_ += consumed;
        switch (event.status) {
            case protocol::FrameStatus::NeedMore:
                unfinished_.add(consumed, framer_.partial_frame(), now);
                partial_deadline_ = now + limits_.partial_frame_timeout;
                break;
            case protocol::FrameStatus::Frame:
                unfinished_.clear();
                on_frame(event, now);
                break;
            case protocol::FrameStatus::Error: {
                const auto started = unfinished_.empty() ? now : unfinished_.started();
                unfinished_.clear();
                on_frame_error(event, started, now);
                break;
            }
        }
    }
    if (eof_ && !stopped_) finish_input(now);
}

bool MbapSession::must_pause(Clock::time_point now) const {
    const auto limit = outstanding_limit(limits_);
    const auto queued = replies_.size();
    if (queued >= limit + kBusySlack) return true;
    // Answers that are ready only wait for the socket: wait with them rather than call the
    // device busy. Busy is for answers the device itself holds back (a delay fault).
    return queued >= limit && replies_.front().ready_at <= now;
}

void MbapSession::on_frame(const protocol::FrameEvent& frame, Clock::time_point now) {
    last_activity_ = now;
    carried_request_ = true;
    const auto request = protocol::to_mbap_header(frame.header);
    ServerStats::bump(stats_.requests);
    if (replies_.size() >= outstanding_limit(limits_)) {
        ServerStats::bump(stats_.busy);
        queue_exception(request, frame.pdu, protocol::ExceptionCode::ServerDeviceBusy, now);
        return;
    }
    if (rules_ && !rules_->permits(role_, frame.header.unit, frame.pdu)) {
        // [SEC]: a request the role does not allow is refused as an illegal function.
        ServerStats::bump(stats_.denied);
        queue_exception(request, frame.pdu, protocol::ExceptionCode::IllegalFunction, now);
        return;
    }
    auto* slot = replies_.push_back();
    if (!slot) return;  // must_pause() keeps room; never reached
    const auto response = protocol::mbap_pdu_room(slot->adu);
    const auto ticket = ++last_ticket_;
    SessionDeferral deferral(host_, ticket, request);
    const auto reply = handler_.handle_or_defer({frame.header.unit, device::Link::Tcp, peer_},
                                                frame.pdu, response, deferral);
    if (!reply) {
        slot->deferred = true;
        slot->ticket = ticket;
        slot->ready_at = Clock::time_point::max();
        return;
    }
    if (reply->action == device::ReplyAction::NoAnswer) {
        replies_.pop_back();
        return;
    }
    fill(*slot, request, *reply, response, now);
}

void MbapSession::fill(PendingReply& slot, const protocol::MbapHeader& request,
                       const device::Reply& reply, std::span<const std::uint8_t> response,
                       Clock::time_point now) {
    switch (reply.action) {
        case device::ReplyAction::NoAnswer:
            slot.size = 0;  // nothing goes out for it; it only keeps its place in the order
            break;
        case device::ReplyAction::Close:
            slot.close = true;
            stopped_ = true;
            break;
        case device::ReplyAction::Answer: {
            const auto size = std::min({reply.size, response.size(), protocol::limits::kMaxPdu});
            slot.size = static_cast<std::uint16_t>(
                protocol::write_mbap_adu(answer_header(request), response.first(size), slot.adu));
            if (size > 0 && (response.front() & protocol::kExceptionBit)) {
                ServerStats::bump(stats_.exceptions);
            }
            break;
        }
    }
    slot.ready_at = now + reply.delay;
}

void MbapSession::answer_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                                  const device::Reply& reply, std::span<const std::uint8_t> pdu,
                                  Clock::time_point now) {
    for (std::size_t i = 0; i < replies_.size(); ++i) {
        PendingReply& slot = replies_.at(i);
        if (!slot.deferred || slot.ticket != ticket) continue;
        slot.deferred = false;
        fill(slot, request, reply, pdu, now);
        process_input(now);  // reading may have waited for room behind it
        return;
    }
}

void MbapSession::on_frame_error(const protocol::FrameEvent& frame, Clock::time_point started,
                                 Clock::time_point now) {
    const auto& header = frame.header;
    const bool length_ok = header.length >= 2 && header.length <= protocol::limits::kMaxPdu + 1;
    if (length_ok) {
        // Protocol id != 0: the framer skipped the frame, the stream is in step [TCPG 4.4.2.2].
        ServerStats::bump(stats_.frames_dropped);
        return;
    }
    if (header.length > protocol::limits::kMaxPdu + 1 &&
        header.protocol_id == protocol::kModbusProtocolId) {
        unfinished_.begin_overlong(protocol::to_mbap_header(header), started);
        partial_deadline_ = now + limits_.partial_frame_timeout;
        return;
    }
    ServerStats::bump(stats_.closed_bad_frame);
    close_after_answers(now);
}

void MbapSession::drop_partial(Clock::time_point now) {
    if (const auto answer = unfinished_.answerable()) {
        const std::uint8_t function[] = {answer->function};
        queue_exception(answer->header, function, protocol::ExceptionCode::IllegalDataValue, now);
    }
    framer_.reset();
    unfinished_.clear();
}

void MbapSession::on_partial_timeout(Clock::time_point now) {
    ServerStats::bump(stats_.frames_dropped);
    // Requests a client sent during the wait, without waiting for this frame's 03, follow its
    // body; they are read again as input, after the 03, instead of being lost as body bytes.
    const auto requests = unfinished_.requests_after_body();
    const auto rest = input_end_ - input_begin_;  // none: the wait consumed every read
    if (!requests.empty() && requests.size() + rest <= input_.size()) {
        std::memmove(input_.data() + requests.size(), input_.data() + input_begin_, rest);
        std::memcpy(input_.data(), requests.data(), requests.size());
        input_begin_ = 0;
        input_end_ = requests.size() + rest;
    }
    drop_partial(now);
}

void MbapSession::on_slow_frame(Clock::time_point now) {
    ServerStats::bump(stats_.closed_slow_frame);
    drop_partial(now);
    close_after_answers(now);
}

void MbapSession::queue_exception(const protocol::MbapHeader& header,
                                  std::span<const std::uint8_t> request,
                                  protocol::ExceptionCode code, Clock::time_point now) {
    auto* slot = replies_.push_back();
    if (!slot) return;
    host_.on_own_answer({header.unit_id, device::Link::Tcp, peer_}, request, code);
    const std::uint8_t pdu[] = {
        static_cast<std::uint8_t>(request.front() | protocol::kExceptionBit),
        static_cast<std::uint8_t>(code)};
    slot->size =
        static_cast<std::uint16_t>(protocol::write_mbap_adu(answer_header(header), pdu, slot->adu));
    slot->ready_at = now;
    ServerStats::bump(stats_.exceptions);
}

void MbapSession::close_after_answers(Clock::time_point now) {
    stopped_ = true;
    if (auto* slot = replies_.push_back()) {
        slot->close = true;
        slot->ready_at = now;
    } else {
        close_now_ = true;
    }
}

std::size_t MbapSession::output(Clock::time_point now, std::span<iovec> out) {
    gathered_ = 0;
    if (replies_.empty()) return 0;
    const auto& head = replies_.front();
    if (head.ready_at > now) {
        // A handler that still owes the answer brings it with answer_deferred(); a delay
        // fault's time is a deadline.
        if (!head.deferred) head_delay_ = std::min(head_delay_, head.ready_at);
        return 0;
    }
    const auto limit = std::min(out.size(), replies_.size());
    while (gathered_ < limit) {
        const auto& reply = replies_.at(gathered_);
        if (reply.close || reply.ready_at > now) break;
        const auto skip = gathered_ == 0 ? head_sent_ : 0;
        out[gathered_++] = {const_cast<std::uint8_t*>(reply.adu.data() + skip), reply.size - skip};
    }
    return gathered_;
}

void MbapSession::sent(std::size_t bytes, Clock::time_point now) {
    // Answers with nothing to send (a deferred "no answer") go with the bytes around them, or
    // with none at all.
    if (gathered_ == 0) return;  // nothing was offered (the queue may hold no slot at all)
    auto written = bytes + head_sent_;
    std::size_t done = 0;
    while (done < gathered_ && written >= replies_.at(done).size) {
        written -= replies_.at(done).size;
        ++done;
    }
    head_sent_ = written;
    gathered_ = 0;
    if (bytes > 0) last_activity_ = now;
    if (done == 0) return;
    replies_.pop_front(done);
    process_input(now);  // reading may have paused for room
}

MbapSession::Ending MbapSession::ending(Clock::time_point now) const {
    if (close_now_) return Ending::Now;
    if (replies_.empty()) return stopped_ ? Ending::AfterAnswers : Ending::Open;
    const auto& head = replies_.front();
    return head.close && head.ready_at <= now ? Ending::AfterAnswers : Ending::Open;
}

Clock::time_point MbapSession::partial_wakeup() const {
    return std::min(partial_deadline_, unfinished_.started() + limits_.frame_limit);
}

Clock::time_point MbapSession::idle_deadline() const {
    const auto timeout = limits_.idle_timeout;
    if (timeout.count() <= 0) return Clock::time_point::max();
    // An answer a fault delays is activity still to come; an answer stuck behind a client
    // that does not read is not.
    auto since = last_activity_;
    if (!replies_.empty()) {
        // An answer the handler still owes is activity to come: no idle close meanwhile.
        if (replies_.front().deferred) return Clock::time_point::max();
        since = std::max(since, replies_.front().ready_at);
    }
    return since + timeout;
}

Clock::time_point MbapSession::deadline() const {
    auto at = std::min(idle_deadline(), head_delay_);
    if (has_partial()) at = std::min(at, partial_wakeup());
    return at;
}

void MbapSession::on_time(Clock::time_point now) {
    if (close_now_) return;
    if (now >= head_delay_) head_delay_ = Clock::time_point::max();
    if (has_partial() && now >= partial_wakeup()) {
        if (now >= partial_deadline_) {
            on_partial_timeout(now);
            process_input(now);
        } else {
            on_slow_frame(now);
        }
    }
    if (now >= idle_deadline()) {
        ServerStats::bump(stats_.closed_idle);
        close_now_ = true;
    }
}

transport::Standing MbapSession::standing(Clock::time_point now) const {
    using transport::Standing;
    if (replies_.empty() && !has_partial())
        return carried_request_ ? Standing::Idle : Standing::Unused;
    // An answer the device holds back (a delay fault, a gateway's line) is not the client's
    // doing.
    if (!replies_.empty() && (replies_.front().deferred || replies_.front().ready_at > now)) {
        return Standing::Busy;
    }
    return now - last_activity_ >= limits_.partial_frame_timeout ? Standing::Stalled
                                                                 : Standing::Busy;
}

}  // namespace mblab::server
