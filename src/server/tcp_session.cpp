#include "server/tcp_session.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/post.hpp>
#include <asio/use_awaitable.hpp>
#include <cerrno>
#include <cstring>
#include <vector>

#include "protocol/adu_writer.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"

namespace mblab::server {

namespace {

constexpr auto use_tuple = asio::experimental::as_tuple(asio::use_awaitable);
// Busy answers a connection may queue past its outstanding limit before the reader stops
// reading (and TCP flow control slows the client down).
constexpr std::size_t kBusySlack = 16;
// Room for the answers queued outside the reader's checks: a timed-out partial frame's
// exception and a close marker.
constexpr std::size_t kReserveSlots = 2;

std::size_t outstanding_limit(const ServerOptions& options) {
    return std::max<std::size_t>(1, options.max_outstanding);
}

protocol::MbapHeader answer_header(const protocol::MbapHeader& request) {
    return {request.transaction_id, 0, 0, request.unit_id};
}

}  // namespace

TcpSession::TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core)
    : executor_(socket.get_executor()),
      core_(std::move(core)),
      delay_timer_(executor_),
      watchdog_timer_(executor_),
      replies_(outstanding_limit(core_->options) + kBusySlack + kReserveSlots),
      last_activity_(Clock::now()) {
    asio::error_code ec;
    fd_ = socket.release(ec);  // on failure the socket closes with the argument
    if (ec) fd_ = -1;
}

TcpSession::~TcpSession() {
    close_socket();
    leave_table();
}

void TcpSession::leave_table() {
    if (!in_table_) return;
    in_table_ = false;
    core_->listener->connections().remove(*this);
    core_->stats.connections_open.fetch_sub(1, std::memory_order_relaxed);
}

void TcpSession::start() {
    core_->listener->connections().add(*this);
    in_table_ = true;
    ServerStats::bump(core_->stats.connections_open);
    if (fd_ < 0 || !core_->poller->add(fd_, shared_from_this(), EPOLLIN)) {
        close();
        return;
    }
    asio::co_spawn(executor_, watchdog_loop(shared_from_this()), asio::detached);
}

transport::Standing TcpSession::standing(Clock::time_point now) const {
    using transport::Standing;
    if (closed_) return Standing::Busy;
    if (replies_.empty() && !has_partial()) return Standing::Idle;
    // An answer the device holds back (a delay fault, a gateway's line) is not the client's
    // doing.
    if (!replies_.empty() && (replies_.front().deferred || replies_.front().ready_at > now)) {
        return Standing::Busy;
    }
    return now - last_activity_ >= core_->options.partial_frame_timeout ? Standing::Stalled
                                                                        : Standing::Busy;
}

void TcpSession::close() {
    if (closed_) return;
    closed_ = true;
    reading_ = false;
    close_socket();
    // Its place is free now, not when the handlers still holding the session have run: a
    // client that reconnects at once to a full server would otherwise be refused.
    leave_table();
    delay_timer_.cancel();
    watchdog_timer_.cancel();
}

void TcpSession::close_socket() {
    if (fd_ < 0) return;
    core_->poller->remove(fd_);
    ::close(fd_);
    fd_ = -1;
}

void TcpSession::shutdown_and_close() {
    if (fd_ >= 0) ::shutdown(fd_, SHUT_WR);
    close();
}

void TcpSession::on_ready(std::uint32_t events) {
    if (events & EPOLLERR) {
        close();  // reset by the peer: nothing can reach it any more
        return;
    }
    if (events & EPOLLOUT) {
        write_blocked_ = false;
        flush(Clock::now());
    }
    if ((events & (EPOLLIN | EPOLLHUP)) && reading_ && !reader_paused_) read_ready();
    // Both directions shut: no answer can go out, and a level-triggered hang-up would repeat.
    if (events & EPOLLHUP) close();
    update_interest();
}

void TcpSession::read_ready() {
    const auto n = ::recv(fd_, input_.data(), input_.size(), MSG_DONTWAIT);
    if (n > 0) {
        input_begin_ = 0;
        input_end_ = static_cast<std::size_t>(n);
        continue_reading();
    } else if (n == 0) {
        on_end_of_input();
    } else if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
        close();
    }
}

void TcpSession::continue_reading() {
    if (process_input() == Progress::Paused) reader_paused_ = true;
}

void TcpSession::resume_reading_soon() {
    // Not from inside the reader or the writer: the input left over is framed on a fresh stack.
    if (!reader_paused_ || resume_posted_) return;
    resume_posted_ = true;
    asio::post(executor_, [self = shared_from_this()] {
        self->resume_posted_ = false;
        if (self->closed_ || !self->reader_paused_) return;
        self->reader_paused_ = false;
        self->continue_reading();
        self->update_interest();
    });
}

void TcpSession::update_interest() {
    if (closed_) return;
    std::uint32_t events = 0;
    if (reading_ && !reader_paused_) events |= EPOLLIN;
    if (write_blocked_) events |= EPOLLOUT;
    core_->poller->modify(fd_, events);
}

void TcpSession::on_end_of_input() {
    // The client finished sending: answer what came, an unfinished frame included (its missing
    // bytes can no longer arrive), then close.
    auto now = Clock::now();
    if (has_partial()) on_partial_timeout(now);
    if (input_begin_ < input_end_) process_input();  // requests recovered after an overlong frame
    if (has_partial()) on_partial_timeout(now);
    reading_ = false;
    flush(now);
}

TcpSession::Progress TcpSession::process_input() {
    auto now = Clock::now();
    while (input_begin_ < input_end_ && reading_) {
        auto input =
            std::span<const std::uint8_t>(input_.data() + input_begin_, input_end_ - input_begin_);
        if (partial_.overlong) {
            if (!partial_.function) partial_.function = input.front();
            partial_.skipped += input.size();
            const auto room = protocol::limits::kMaxPdu - overlong_body_.size();
            const auto kept = input.first(std::min(input.size(), room));
            overlong_body_.insert(overlong_body_.end(), kept.begin(), kept.end());
            input_begin_ = input_end_;
            if (partial_.skipped > protocol::limits::kMaxPdu) {
                // The body really is longer than any PDU: not a length typo but a flood.
                ServerStats::bump(core_->stats.closed_bad_frame);
                close_after_answers(now);
            } else {
                arm_partial_deadline(now);
            }
            continue;
        }
        if (must_pause(now)) {
            flush(now);
            if (must_pause(now)) return Progress::Paused;
        }
        std::size_t consumed = 0;
        auto event = framer_.feed(input, consumed);
        input_begin_ += consumed;
        switch (event.status) {
            case protocol::FrameStatus::NeedMore:
                on_partial_bytes(input.first(consumed), now);
                break;
            case protocol::FrameStatus::Frame:
                partial_ = {};
                on_frame(event, now);
                break;
            case protocol::FrameStatus::Error: {
                const auto started = partial_.bytes > 0 ? partial_.started : now;
                partial_ = {};
                on_frame_error(event, started, now);
                break;
            }
        }
    }
    flush(now);
    return reading_ ? Progress::Consumed : Progress::Stopped;
}

bool TcpSession::must_pause(Clock::time_point now) {
    auto limit = outstanding_limit(core_->options);
    auto queued = replies_.size();
    if (queued >= limit + kBusySlack) return true;
    // Answers that are ready only wait for the socket: wait with them rather than call the
    // device busy. Busy is for answers the device itself holds back (a delay fault).
    return queued >= limit && replies_.front().ready_at <= now;
}

void TcpSession::on_partial_bytes(std::span<const std::uint8_t> bytes, Clock::time_point now) {
    if (partial_.bytes == 0) partial_.started = now;
    auto function_at = protocol::limits::kMbapHeader;
    if (partial_.bytes <= function_at && function_at < partial_.bytes + bytes.size()) {
        partial_.function = bytes[function_at - partial_.bytes];
    }
    partial_.bytes += bytes.size();
    partial_.header = framer_.partial_header();
    arm_partial_deadline(now);
}

void TcpSession::arm_partial_deadline(Clock::time_point now) {
    partial_deadline_ = now + core_->options.partial_frame_timeout;
    // The watchdog may be asleep until a later idle deadline: wake it to sleep less.
    if (watchdog_timer_.expiry() > partial_wakeup()) watchdog_timer_.cancel();
}

Clock::time_point TcpSession::partial_wakeup() const {
    return std::min(partial_deadline_, partial_.started + core_->options.frame_limit);
}

void TcpSession::on_frame(const protocol::FrameEvent& frame, Clock::time_point now) {
    last_activity_ = now;
    ServerStats::bump(core_->stats.requests);
    if (replies_.size() >= outstanding_limit(core_->options)) {
        ServerStats::bump(core_->stats.busy);
        if (core_->options.on_busy_reply) core_->options.on_busy_reply(frame.unit);
        queue_exception(frame.mbap, frame.pdu.front(), protocol::ExceptionCode::ServerDeviceBusy,
                        now);
        return;
    }
    auto* slot = replies_.push_back();
    if (!slot) return;  // must_pause() keeps room; never reached
    auto response = std::span(slot->adu).subspan(protocol::limits::kMbapHeader);
    // Lends the handler a way to answer later; only a deferring handler uses it.
    struct SessionDeferral final : device::Deferral {
        TcpSession& session;
        std::uint32_t ticket;
        const protocol::MbapHeader& request;
        SessionDeferral(TcpSession& s, std::uint32_t t, const protocol::MbapHeader& r)
            : session(s), ticket(t), request(r) {}
        device::DeferredDone take() override { return session.deferred_done(ticket, request); }
    };
    const auto ticket = ++last_ticket_;
    SessionDeferral deferral(*this, ticket, frame.mbap);
    auto reply = core_->handler.handle_or_defer({frame.unit, device::Link::Tcp}, frame.pdu,
                                                response, deferral);
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
    fill(*slot, frame.mbap, *reply, response, now);
}

void TcpSession::fill(PendingReply& slot, const protocol::MbapHeader& request,
                      const device::Reply& reply, std::span<const std::uint8_t> response,
                      Clock::time_point now) {
    switch (reply.action) {
        case device::ReplyAction::NoAnswer:
            slot.size = 0;  // nothing goes out for it; it only keeps its place in the order
            break;
        case device::ReplyAction::Close:
            slot.close = true;
            reading_ = false;
            break;
        case device::ReplyAction::Answer: {
            auto size = std::min({reply.size, response.size(), protocol::limits::kMaxPdu});
            slot.size = static_cast<std::uint16_t>(
                protocol::write_mbap_adu(answer_header(request), response.first(size), slot.adu));
            if (size > 0 && (response.front() & protocol::kExceptionBit)) {
                ServerStats::bump(core_->stats.exceptions);
            }
            break;
        }
    }
    slot.ready_at = now + reply.delay;
}

device::DeferredDone TcpSession::deferred_done(std::uint32_t ticket,
                                               const protocol::MbapHeader& request) {
    // Called on the handler's thread: the answer is copied and handed to the session's own.
    return [weak = weak_from_this(), executor = executor_, ticket, request](
               const device::Reply& reply, std::span<const std::uint8_t> pdu) {
        asio::post(executor, [weak, ticket, request, reply,
                              bytes = std::vector<std::uint8_t>(pdu.begin(), pdu.end())] {
            if (auto self = weak.lock()) self->on_deferred(ticket, request, reply, bytes);
        });
    };
}

void TcpSession::on_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                             const device::Reply& reply, std::span<const std::uint8_t> pdu) {
    if (closed_) return;
    for (std::size_t i = 0; i < replies_.size(); ++i) {
        PendingReply& slot = replies_.at(i);
        if (!slot.deferred || slot.ticket != ticket) continue;
        slot.deferred = false;
        auto now = Clock::now();
        fill(slot, request, reply, pdu, now);
        flush(now);  // the answers behind it may have waited for it
        resume_reading_soon();
        return;
    }
}

void TcpSession::on_frame_error(const protocol::FrameEvent& frame, Clock::time_point started,
                                Clock::time_point now) {
    const auto& header = frame.mbap;
    bool length_ok = header.length >= 2 && header.length <= protocol::limits::kMaxPdu + 1;
    if (length_ok) {
        // Protocol id != 0: the framer skipped the frame, the stream is in step [TCPG 4.4.2.2].
        ServerStats::bump(core_->stats.frames_dropped);
        return;
    }
    if (header.length > protocol::limits::kMaxPdu + 1 && header.protocol_id == 0) {
        // Seed 000 9.1.3 sends length 0xFF with a 6-byte body: wait for the body like any
        // unfinished frame, then answer 03 and carry on.
        partial_.header = header;
        partial_.bytes = protocol::limits::kMbapHeader;
        partial_.started = started;
        partial_.overlong = true;
        arm_partial_deadline(now);
        return;
    }
    ServerStats::bump(core_->stats.closed_bad_frame);
    close_after_answers(now);
}

void TcpSession::drop_partial(Clock::time_point now) {
    if (partial_.header && partial_.header->protocol_id == 0 && partial_.function) {
        queue_exception(*partial_.header, *partial_.function,
                        protocol::ExceptionCode::IllegalDataValue, now);
    }
    framer_.reset();
    partial_ = {};
    overlong_body_.clear();
}

void TcpSession::on_partial_timeout(Clock::time_point now) {
    std::vector<std::uint8_t> body;
    body.swap(overlong_body_);
    ServerStats::bump(core_->stats.frames_dropped);
    drop_partial(now);
    if (body.size() < 2) return;
    // Requests a client sent during the wait, without waiting for this frame's 03, follow its
    // body; they are read again as input, after the 03, instead of being lost as body bytes.
    const auto from = 1 + protocol::mbap_resync_offset(std::span(body).subspan(1));
    const auto count = body.size() - from;
    const auto rest = input_end_ - input_begin_;  // none: the wait consumed every read
    if (count == 0 || count + rest > input_.size()) return;
    std::memmove(input_.data() + count, input_.data() + input_begin_, rest);
    std::memcpy(input_.data(), body.data() + from, count);
    input_begin_ = 0;
    input_end_ = count + rest;
}

void TcpSession::on_slow_frame(Clock::time_point now) {
    ServerStats::bump(core_->stats.closed_slow_frame);
    drop_partial(now);
    close_after_answers(now);
}

void TcpSession::queue_exception(const protocol::MbapHeader& header, std::uint8_t function,
                                 protocol::ExceptionCode code, Clock::time_point now) {
    auto* slot = replies_.push_back();
    if (!slot) return;
    const std::uint8_t pdu[] = {static_cast<std::uint8_t>(function | protocol::kExceptionBit),
                                static_cast<std::uint8_t>(code)};
    slot->size =
        static_cast<std::uint16_t>(protocol::write_mbap_adu(answer_header(header), pdu, slot->adu));
    slot->ready_at = now;
    ServerStats::bump(core_->stats.exceptions);
}

void TcpSession::close_after_answers(Clock::time_point now) {
    reading_ = false;
    if (auto* slot = replies_.push_back()) {
        slot->close = true;
        slot->ready_at = now;
    } else {
        close();
    }
}

void TcpSession::flush(Clock::time_point now) {
    std::array<iovec, kMaxGather> buffers;
    while (!closed_ && !write_blocked_) {
        if (replies_.empty()) {
            if (!reading_) shutdown_and_close();
            return;
        }
        const auto& head = replies_.front();
        if (head.ready_at > now) {
            if (!head.deferred) arm_delay(head.ready_at);
            return;
        }
        if (head.close) {
            shutdown_and_close();
            return;
        }
        const auto count = gather_ready(now, buffers);
        std::size_t wanted = 0;
        for (std::size_t i = 0; i < count; ++i)
            wanted += buffers[i].iov_len;
        ssize_t sent = 0;
        if (count == 1) {
            // The usual case, one answer: send() is a little cheaper than sendmsg().
            sent =
                ::send(fd_, buffers[0].iov_base, buffers[0].iov_len, MSG_NOSIGNAL | MSG_DONTWAIT);
        } else {
            msghdr message{};
            message.msg_iov = buffers.data();
            message.msg_iovlen = count;
            sent = ::sendmsg(fd_, &message, MSG_NOSIGNAL | MSG_DONTWAIT);
        }
        if (sent < 0) {
            if (errno == EINTR) continue;
            if (errno != EAGAIN && errno != EWOULDBLOCK) {
                close();
                return;
            }
            sent = 0;
        }
        if (sent > 0) consume_sent(count, static_cast<std::size_t>(sent), now);
        if (static_cast<std::size_t>(sent) < wanted) {
            // The client is not reading fast enough: wait for room in the socket.
            write_blocked_ = true;
            update_interest();
        }
    }
}

void TcpSession::arm_delay(Clock::time_point until) {
    if (delay_until_ == until) return;  // already armed for it
    delay_until_ = until;
    delay_timer_.expires_at(until);
    delay_timer_.async_wait([self = shared_from_this()](const asio::error_code& ec) {
        if (ec || self->closed_) return;
        self->delay_until_ = {};
        self->flush(Clock::now());
    });
}

std::size_t TcpSession::gather_ready(Clock::time_point now, std::span<iovec> out) const {
    std::size_t count = 0;
    auto limit = std::min(out.size(), replies_.size());
    while (count < limit) {
        const auto& reply = replies_.at(count);
        if (reply.close || reply.ready_at > now) break;
        auto skip = count == 0 ? head_sent_ : 0;
        out[count++] = {const_cast<std::uint8_t*>(reply.adu.data() + skip), reply.size - skip};
    }
    return count;
}

void TcpSession::consume_sent(std::size_t count, std::size_t written, Clock::time_point now) {
    written += head_sent_;
    std::size_t done = 0;
    while (done < count && written >= replies_.at(done).size) {
        written -= replies_.at(done).size;
        ++done;
    }
    replies_.pop_front(done);
    head_sent_ = written;
    last_activity_ = now;
    if (done > 0) resume_reading_soon();
}

Clock::time_point TcpSession::idle_deadline() const {
    auto timeout = core_->options.idle_timeout;
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

asio::awaitable<void> TcpSession::watchdog_loop(std::shared_ptr<TcpSession> /*self*/) {
    while (!closed_) {
        auto deadline = idle_deadline();
        if (has_partial()) deadline = std::min(deadline, partial_wakeup());
        watchdog_timer_.expires_at(deadline);
        co_await watchdog_timer_.async_wait(use_tuple);
        if (closed_) break;
        auto now = Clock::now();
        if (has_partial() && now >= partial_wakeup()) {
            if (now >= partial_deadline_) {
                on_partial_timeout(now);
                if (input_begin_ < input_end_ && !reader_paused_) {
                    continue_reading();
                    update_interest();
                }
            } else {
                on_slow_frame(now);
            }
            flush(now);
        }
        if (now >= idle_deadline()) {
            ServerStats::bump(core_->stats.closed_idle);
            close();
            break;
        }
    }
}

}  // namespace mblab::server
