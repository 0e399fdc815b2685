#include "server/tcp_session.hpp"

#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <array>
#include <asio/post.hpp>
#include <cerrno>
#include <cstring>
#include <vector>

#include "server/bare_pdu.hpp"

namespace mblab::server {

namespace {

MbapSessionLimits limits_of(const ServerOptions& options) {
    return {options.idle_timeout, options.partial_frame_timeout, options.frame_limit,
            options.max_outstanding};
}

// A TLS record's worth: one read takes a whole record when the client sent one.
constexpr std::size_t kCipherChunk = 16 * 1024 + 512;
// Answers gathered into one TLS record rather than a record each.
constexpr std::size_t kPlainBatch = 16 * 1024;

// Roles without rules: every request is refused (deny by default).
const device::RoleRules kNoRules;

}  // namespace

TcpSession::TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core)
    : executor_(socket.get_executor()),
      core_(std::move(core)),
      session_(core_->handler, limits_of(core_->options), core_->stats, *this, Clock::now()),
      timer_(executor_) {
    asio::error_code ec;
    fd_ = socket.release(ec);  // on failure the socket closes with the argument
    if (ec) fd_ = -1;
    if (core_->options.tls) {
        tls_ = std::make_unique<security::TlsChannel>(core_->options.tls,
                                                      security::TlsChannel::Side::Server);
        handshake_deadline_ = Clock::now() + core_->options.handshake_limit;
    }
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
    arm_timer();
}

transport::Standing TcpSession::standing(Clock::time_point now) const {
    if (closed_) return transport::Standing::Busy;
    if (tls_ && tls_->state() == security::TlsChannel::State::Handshaking) {
        return transport::Standing::Handshaking;
    }
    return session_.standing(now);
}

void TcpSession::close() {
    if (closed_) return;
    closed_ = true;
    close_socket();
    // Its place is free now, not when the handlers still holding the session have run: a
    // client that reconnects at once to a full server would otherwise be refused.
    leave_table();
    timer_.cancel();
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
    const auto now = Clock::now();
    if (events & EPOLLOUT) {
        write_blocked_ = false;
        flush(now);
    }
    if ((events & (EPOLLIN | EPOLLHUP)) && !closed_ && wants_read()) read_ready(now);
    // Both directions shut: no answer can go out, and a level-triggered hang-up would repeat.
    if (events & EPOLLHUP) close();
    settle();
}

bool TcpSession::wants_read() const {
    if (tls_ && tls_->state() == security::TlsChannel::State::Handshaking) return true;
    return session_.wants_input();
}

void TcpSession::end_input(Clock::time_point now) {
    if (input_ended_) return;
    input_ended_ = true;
    session_.end_of_input(now);
}

void TcpSession::read_ready(Clock::time_point now) {
    if (tls_) {
        read_tls(now);
        return;
    }
    const auto space = session_.input_space();
    const auto n = ::recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n > 0) {
        session_.received(static_cast<std::size_t>(n), now);
    } else if (n == 0) {
        session_.end_of_input(now);
    } else {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) close();
        return;
    }
    flush(now);
}

void TcpSession::read_tls(Clock::time_point now) {
    std::array<std::uint8_t, kCipherChunk> cipher;
    const auto n = ::recv(fd_, cipher.data(), cipher.size(), MSG_DONTWAIT);
    if (n < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) close();
        return;
    }
    if (n > 0) tls_->received(std::span(cipher).first(static_cast<std::size_t>(n)));
    pump_tls(now);
    // A FIN without close_notify: the requests that came whole are still answered.
    if (n == 0 && !closed_) end_input(now);
    flush(now);
}

std::size_t TcpSession::pump_tls(Clock::time_point now) {
    using State = security::TlsChannel::State;
    if (tls_->state() == State::Handshaking) {
        tls_->read({});
        if (tls_->state() == State::Open) on_handshake();
    }
    std::size_t handed = 0;
    while (tls_->state() == State::Open && session_.wants_input()) {
        const auto got = tls_->read(session_.input_space());
        if (got == 0) break;
        if (!seen_plaintext_) {
            seen_plaintext_ = true;
            if (is_bare_pdu(session_.input_space().first(got))) {
                refuse_client(
                    "it sent a bare PDU without the MBAP header (an early draft's framing, "
                    "pymodbus's TLS framer); Modbus/TCP Security carries MBAP inside TLS");
                return handed;
            }
        }
        handed += got;
        session_.received(got, now);
    }
    switch (tls_->state()) {
        case State::Handshaking:
        case State::Open:
            break;
        case State::Closed:  // close_notify: answer what came, then close
            end_input(now);
            break;
        case State::Failed:
            if (handshake_deadline_ != Clock::time_point::max()) {
                refuse_handshake(tls_->error());
            }
            send_cipher();  // the alert that tells the client why
            close();
            break;
    }
    return handed;
}

void TcpSession::on_handshake() {
    handshake_deadline_ = Clock::time_point::max();
    ServerStats::bump(core_->stats.tls_handshakes);
    const auto& peer = tls_->peer();
    if (peer.resumed) ServerStats::bump(core_->stats.tls_resumed);
    std::optional<std::string> role;
    if (peer.role.kind == security::RoleReading::Kind::Role) role = peer.role.role;
    session_.authorize(core_->options.roles ? *core_->options.roles : kNoRules, std::move(role));
}

void TcpSession::refuse_client(const std::string& reason) {
    ServerStats::bump(core_->stats.tls_refused);
    if (core_->options.on_tls_refused) core_->options.on_tls_refused(reason);
    tls_->close();
    send_cipher();
    close();
}

void TcpSession::refuse_handshake(const std::string& reason) {
    handshake_deadline_ = Clock::time_point::max();
    ServerStats::bump(core_->stats.tls_refused);
    if (core_->options.on_tls_refused) core_->options.on_tls_refused(reason);
}

bool TcpSession::send_cipher() {
    for (auto out = tls_->output(); !out.empty() && !closed_; out = tls_->output()) {
        const auto n = ::send(fd_, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR) continue;
            if (errno == EAGAIN || errno == EWOULDBLOCK) {
                write_blocked_ = true;
            } else {
                close();
            }
            return false;
        }
        tls_->sent(static_cast<std::size_t>(n));
    }
    return !closed_;
}

void TcpSession::flush_tls(Clock::time_point now) {
    std::array<iovec, MbapSession::kMaxGather> buffers;
    std::array<std::uint8_t, kPlainBatch> batch;
    while (!closed_ && !write_blocked_) {
        if (!send_cipher()) return;
        if (tls_->state() != security::TlsChannel::State::Open) return;
        const auto count = session_.output(now, buffers);
        if (count == 0) {
            switch (session_.ending(now)) {
                case MbapSession::Ending::Open:
                    return;
                case MbapSession::Ending::AfterAnswers:
                    tls_->close();
                    send_cipher();
                    shutdown_and_close();
                    return;
                case MbapSession::Ending::Now:
                    close();
                    return;
            }
        }
        // The answers gathered go out as one record: a record each would cost a MAC and a
        // header per answer to a pipelining client.
        std::size_t size = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const auto length = std::min(buffers[i].iov_len, batch.size() - size);
            std::memcpy(batch.data() + size, buffers[i].iov_base, length);
            size += length;
        }
        if (!tls_->write(std::span(batch).first(size))) {
            close();
            return;
        }
        session_.sent(size, now);
    }
}

void TcpSession::flush(Clock::time_point now) {
    if (tls_) {
        flush_tls(now);
        return;
    }
    std::array<iovec, MbapSession::kMaxGather> buffers;
    while (!closed_ && !write_blocked_) {
        const auto count = session_.output(now, buffers);
        if (count == 0) {
            switch (session_.ending(now)) {
                case MbapSession::Ending::Open:
                    return;
                case MbapSession::Ending::AfterAnswers:
                    shutdown_and_close();
                    return;
                case MbapSession::Ending::Now:
                    close();
                    return;
            }
        }
        std::size_t wanted = 0;
        for (std::size_t i = 0; i < count; ++i)
            wanted += buffers[i].iov_len;
        ssize_t sent = 0;
        if (wanted == 0) {
            // Only answers with nothing to send (a deferred "no answer"): no system call.
        } else if (count == 1) {
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
        session_.sent(static_cast<std::size_t>(sent), now);
        // The client is not reading fast enough: wait for room in the socket.
        if (static_cast<std::size_t>(sent) < wanted) write_blocked_ = true;
    }
}

void TcpSession::settle() {
    if (closed_) return;
    // Records decrypted but not yet handed over wait for the session to take input again; no
    // socket event would bring them.
    if (tls_) {
        const auto now = Clock::now();
        while (!closed_ && session_.wants_input() && tls_->has_input() && pump_tls(now) > 0) {
            flush(now);
        }
        if (closed_) return;
    }
    std::uint32_t events = 0;
    if (wants_read()) events |= EPOLLIN;
    if (write_blocked_) events |= EPOLLOUT;
    core_->poller->modify(fd_, events);
    arm_timer();
}

void TcpSession::arm_timer() {
    const auto at = std::min(session_.deadline(), handshake_deadline_);
    // The timer wakes first; on_time() then finds nothing due.
    if (timer_pending_ && at >= timer_at_) return;
    // A wait is always pending while the session is open, at time_point::max() when nothing is
    // due: its handler is what keeps an open session alive (the poller only watches it).
    timer_pending_ = true;
    timer_at_ = at;
    timer_.expires_at(at);
    timer_.async_wait([self = shared_from_this()](const asio::error_code& ec) {
        if (!ec && !self->closed_) self->on_timer();
    });
}

void TcpSession::on_timer() {
    timer_pending_ = false;
    const auto now = Clock::now();
    if (now >= handshake_deadline_) {
        refuse_handshake("the TLS handshake did not finish within the handshake limit");
        close();
        return;
    }
    session_.on_time(now);
    if (session_.ending(now) == MbapSession::Ending::Now) {
        close();
        return;
    }
    flush(now);
    settle();
}

device::DeferredDone TcpSession::route_deferred(std::uint32_t ticket,
                                                const protocol::MbapHeader& request) {
    // Called on the handler's thread: the answer is copied and handed to the session's own.
    return [weak = weak_from_this(), executor = executor_, ticket, request](
               const device::Reply& reply, std::span<const std::uint8_t> pdu) {
        asio::post(executor, [weak, ticket, request, reply,
                              bytes = std::vector<std::uint8_t>(pdu.begin(), pdu.end())] {
            const auto self = weak.lock();
            if (!self || self->closed_) return;
            const auto now = Clock::now();
            self->session_.answer_deferred(ticket, request, reply, bytes, now);
            self->flush(now);
            self->settle();
        });
    };
}

void TcpSession::on_busy_reply(std::uint8_t unit) {
    if (core_->options.on_busy_reply) core_->options.on_busy_reply(unit);
}

}  // namespace mblab::server
