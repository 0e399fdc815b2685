#include "server/tcp_session.hpp"

#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <array>
#include <asio/post.hpp>
#include <cerrno>
#include <vector>

namespace mblab::server {

namespace {

MbapSessionLimits limits_of(const ServerOptions& options) {
    return {options.idle_timeout, options.partial_frame_timeout, options.frame_limit,
            options.max_outstanding};
}

}  // namespace

TcpSession::TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core)
    : executor_(socket.get_executor()),
      core_(std::move(core)),
      session_(core_->handler, limits_of(core_->options), core_->stats, *this, Clock::now()),
      timer_(executor_) {
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
    arm_timer();
}

transport::Standing TcpSession::standing(Clock::time_point now) const {
    return closed_ ? transport::Standing::Busy : session_.standing(now);
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
    if ((events & (EPOLLIN | EPOLLHUP)) && !closed_ && session_.wants_input()) read_ready(now);
    // Both directions shut: no answer can go out, and a level-triggered hang-up would repeat.
    if (events & EPOLLHUP) close();
    settle();
}

void TcpSession::read_ready(Clock::time_point now) {
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

void TcpSession::flush(Clock::time_point now) {
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
    std::uint32_t events = 0;
    if (session_.wants_input()) events |= EPOLLIN;
    if (write_blocked_) events |= EPOLLOUT;
    core_->poller->modify(fd_, events);
    arm_timer();
}

void TcpSession::arm_timer() {
    const auto at = session_.deadline();
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
