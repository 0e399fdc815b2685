#include "server/mbap_driver.hpp"

#include <algorithm>
#include <array>
#include <optional>

#include "server/bare_pdu.hpp"

namespace mblab::server {

namespace {

using Status = transport::Io::Status;

// Roles without rules: every request is refused (deny by default).
const device::RoleRules kNoRules;

}  // namespace

MbapDriver::MbapDriver(transport::Channel& channel, MbapSession& session,
                       const ServerOptions& options, ServerStats& stats, Clock::time_point now)
    : channel_(channel),
      session_(session),
      options_(options),
      stats_(stats),
      tls_(options.tls != nullptr) {
    if (tls_) handshake_deadline_ = now + options.handshake_limit;
}

bool MbapDriver::wants_read() const {
    if (closed_) return false;
    if (lingering()) return !input_ended_;
    if (channel_.handshaking()) return true;
    return session_.wants_input();
}

Clock::time_point MbapDriver::deadline() const {
    if (lingering()) return linger_.deadline();
    return std::min({session_.deadline(), handshake_deadline_, rest_at_});
}

void MbapDriver::readable(Clock::time_point now) {
    input_may_remain_ = false;
    if (!wants_read()) return;
    if (lingering()) {
        discard(now);
        return;
    }
    moved(now);
    take(now);
    flush(now);
    drain(now);
    rest_if_due(now);
}

void MbapDriver::writable(Clock::time_point now) {
    write_blocked_ = false;
    if (lingering()) {
        send_end();
        return;
    }
    flush(now);
    drain(now);
}

void MbapDriver::rest_if_due(Clock::time_point now) {
    if (now < rest_at_ || closed_ || lingering()) return;
    rest_at_ = channel_.rest() ? Clock::time_point::max() : now + kRestAfter;
}

void MbapDriver::on_time(Clock::time_point now) {
    if (closed_) return;
    if (lingering()) {
        // A client that neither ends nor stops sending: its reset cannot cost it much now.
        if (linger_.over(now)) closed_ = true;
        return;
    }
    if (now >= handshake_deadline_) {
        refuse_handshake("the TLS handshake did not finish within the handshake limit");
        closed_ = true;
        return;
    }
    session_.on_time(now);
    if (session_.ending(now) == MbapSession::Ending::Now) {
        closed_ = true;
        return;
    }
    flush(now);
    drain(now);
    rest_if_due(now);
}

void MbapDriver::answer_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                                 const device::Reply& reply, std::span<const std::uint8_t> pdu,
                                 Clock::time_point now) {
    if (closed_ || lingering()) return;
    session_.answer_deferred(ticket, request, reply, pdu, now);
    flush(now);
    drain(now);
}

void MbapDriver::drain(Clock::time_point now) {
    while (!closed_ && !lingering() && session_.wants_input() && channel_.has_input()) {
        const bool took = take(now);
        // Also after a read that found the end (a close_notify behind the last request): the
        // answers and the end go out now, as nothing on the socket would bring them later.
        flush(now);
        if (!took) return;
    }
}

void MbapDriver::end_input(Clock::time_point now) {
    if (input_ended_) return;
    input_ended_ = true;
    session_.end_of_input(now);
}

bool MbapDriver::take(Clock::time_point now) {
    const bool was_handshaking = channel_.handshaking();
    const auto space = session_.input_space();
    const auto io = channel_.read(space);
    input_may_remain_ = io.status == Status::Done && channel_.input_may_remain();
    if (was_handshaking && !channel_.handshaking()) {
        if (const auto peer = channel_.peer(); peer.tls != nullptr) on_handshake(*peer.tls);
    }
    switch (io.status) {
        case Status::Done:
            break;
        case Status::WouldBlock:
            return false;
        case Status::EndOfInput:
            // A FIN without close_notify, or close_notify: the requests that came whole are
            // still answered, unless the end took output with it (TLS 1.2's close_notify: ours
            // answers it, then the FIN). Before the handshake ended nothing can come any more.
            if (channel_.handshaking()) {
                closed_ = true;
            } else if (channel_.output_ended()) {
                linger(now);
            } else {
                end_input(now);
            }
            return false;
        case Status::Failed:
            // A TLS failure (no errno) in the handshake is a refusal, its alert already sent.
            if (handshake_deadline_ != Clock::time_point::max() && io.code == 0) {
                refuse_handshake(channel_.error());
            }
            closed_ = true;
            return false;
    }
    if (tls_ && !seen_plaintext_) {
        seen_plaintext_ = true;
        if (is_bare_pdu(space.first(io.bytes))) {
            refuse_client(
                "it sent a bare PDU without the MBAP header (an early draft's framing, "
                "pymodbus's TLS framer); Modbus/TCP Security carries MBAP inside TLS",
                now);
            return false;
        }
    }
    session_.received(io.bytes, now);
    return true;
}

void MbapDriver::flush(Clock::time_point now) {
    std::array<iovec, MbapSession::kMaxGather> buffers;
    while (!closed_ && !write_blocked_ && !lingering()) {
        if (channel_.wants_write()) {
            if (channel_.flush().status == Status::Failed) {
                closed_ = true;
                return;
            }
            if (channel_.wants_write()) {
                write_blocked_ = true;
                return;
            }
        }
        if (channel_.handshaking()) return;
        const auto count = session_.output(now, buffers);
        if (count == 0) {
            switch (session_.ending(now)) {
                case MbapSession::Ending::Open:
                    return;
                case MbapSession::Ending::AfterAnswers:
                    linger(now);
                    return;
                case MbapSession::Ending::Now:
                    closed_ = true;
                    return;
            }
        }
        std::size_t wanted = 0;
        for (std::size_t i = 0; i < count; ++i)
            wanted += buffers[i].iov_len;
        const auto io = channel_.writev(std::span(buffers).first(count));
        if (io.status == Status::Failed) {
            closed_ = true;
            return;
        }
        session_.sent(io.bytes, now);
        // Also an answer the session's clock let out (a delayed one): its record took the
        // buffers again.
        if (io.bytes > 0) moved(now);
        // The client is not reading fast enough: wait for room. A TLS record takes at most a
        // batch of answers; the rest goes in the next one at once.
        if (tls_ ? channel_.wants_write() || io.status == Status::WouldBlock : io.bytes < wanted) {
            write_blocked_ = true;
        }
    }
}

void MbapDriver::linger(Clock::time_point now) {
    channel_.shutdown_write();
    // A session whose close_notify met the client's has nothing more to read.
    if (channel_.output_ended()) input_ended_ = true;
    linger_.start(now);
    send_end();
    if (!closed_ && !input_ended_) discard(now);
}

void MbapDriver::send_end() {
    // The rest of a close_notify, then the FIN behind it (transport::TlsStream).
    if (channel_.wants_write() && channel_.flush().status == Status::Failed) {
        closed_ = true;
        return;
    }
    write_blocked_ = channel_.wants_write();
    // A client that ended its input has nothing left to send: the end out is all that was owed.
    if (input_ended_ && !write_blocked_) closed_ = true;
}

void MbapDriver::discard(Clock::time_point now) {
    for (int reads = 0; reads < transport::Linger::kReadsPerWake; ++reads) {
        switch (channel_.discard_input().status) {
            case Status::Done:
                linger_.heard(now);
                continue;
            case Status::WouldBlock:
                return;
            case Status::EndOfInput:
                input_ended_ = true;
                send_end();
                return;
            case Status::Failed:
                closed_ = true;
                return;
        }
    }
    input_may_remain_ = true;
}

void MbapDriver::on_handshake(const security::TlsPeer& peer) {
    handshake_deadline_ = Clock::time_point::max();
    // The handshake filled the buffers; the client has shown no use for them yet (many connect
    // once and poll seldom), so they go back at once, and its first request takes them again.
    rest_at_ = Clock::time_point::min();
    ServerStats::bump(stats_.tls_handshakes);
    if (peer.resumed) ServerStats::bump(stats_.tls_resumed);
    std::optional<std::string> role;
    if (peer.role.kind == security::RoleReading::Kind::Role) role = peer.role.role;
    session_.authorize(options_.roles ? *options_.roles : kNoRules, std::move(role));
}

void MbapDriver::refuse_client(const std::string& reason, Clock::time_point now) {
    ServerStats::bump(stats_.tls_refused);
    if (options_.on_tls_refused) options_.on_tls_refused(reason);
    // The lingering end: closed at once, the rest of what the client sent would reset the
    // connection and the client would read a reset, not the refusal.
    linger(now);
}

void MbapDriver::refuse_handshake(const std::string& reason) {
    handshake_deadline_ = Clock::time_point::max();
    ServerStats::bump(stats_.tls_refused);
    if (options_.on_tls_refused) options_.on_tls_refused(reason);
}

}  // namespace mblab::server
