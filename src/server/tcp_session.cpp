#include "server/tcp_session.hpp"

#include <sys/socket.h>

#include <asio/post.hpp>
#include <cstring>
#include <vector>

#include "transport/tcp_url.hpp"

namespace mblab::server {

namespace {

MbapSessionLimits limits_of(const ServerOptions& options) {
    return {options.idle_timeout, options.partial_frame_timeout, options.frame_limit,
            options.max_outstanding};
}

// Input, and the client's FIN (which may come with its last request, and stay unread).
constexpr std::uint32_t kInput = EPOLLIN | EPOLLRDHUP;

int take_descriptor(asio::ip::tcp::socket& socket) {
    asio::error_code ec;
    const int fd = socket.release(ec);  // on failure the socket closes with the argument
    return ec ? -1 : fd;
}

// Modbus/TCP Security: the socket carries a TLS session and the MBAP session sees plaintext.
std::unique_ptr<transport::TlsStream> tls_over(transport::SocketChannel& socket,
                                               const ServerOptions& options) {
    if (!options.tls) return nullptr;
    return std::make_unique<transport::TlsStream>(socket, options.tls,
                                                  transport::TlsStream::Side::Server);
}

}  // namespace

TcpSession::TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core)
    : executor_(socket.get_executor()),
      fd_(take_descriptor(socket)),
      core_(std::move(core)),
      socket_(fd_),
      tls_(tls_over(socket_, core_->options)),
      channel_(tls_ ? static_cast<transport::Channel&>(*tls_) : socket_),
      session_(core_->handler, limits_of(core_->options), core_->stats, *this, Clock::now()),
      driver_(channel_, session_, core_->options, core_->stats, Clock::now()),
      timer_(executor_) {
    const auto peer = channel_.peer();
    asio::ip::tcp::endpoint endpoint;
    if (peer.address_size > 0 && peer.address_size <= endpoint.capacity()) {
        std::memcpy(endpoint.data(), &peer.address, peer.address_size);
        endpoint.resize(peer.address_size);
        session_.set_peer(transport::endpoint_text(endpoint));
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
    if (fd_ < 0 || !core_->poller->add(fd_, *this, kInput)) {
        close();
        return;
    }
    arm_timer();
}

transport::Standing TcpSession::standing(Clock::time_point now) const {
    if (closed_) return transport::Standing::Busy;
    if (driver_.lingering()) return transport::Standing::Ending;
    if (driver_.handshaking()) return transport::Standing::Handshaking;
    return session_.standing(now);
}

void TcpSession::close() {
    if (closed_) return;
    closed_ = true;
    driver_.stop();
    close_socket();
    // Its place is free now, not when the handlers still holding the session have run: a
    // client that reconnects at once to a full server would otherwise be refused.
    leave_table();
    timer_.cancel();
}

void TcpSession::close_socket() {
    if (fd_ < 0) return;
    core_->poller->remove(fd_);
    channel_.close();
    fd_ = -1;
}

bool TcpSession::on_ready(std::uint32_t events) {
    if (events & EPOLLERR) {
        close();  // reset by the peer: nothing can reach it any more
        return false;
    }
    const auto now = Clock::now();
    if (events & EPOLLOUT) driver_.writable(now);
    if (events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP)) driver_.readable(now);
    // Both directions shut: no answer can go out, and a level-triggered hang-up would repeat.
    // A lingering session reads on to the end (a read never waits after a hang-up): closing with
    // input unread would reset the connection.
    if ((events & EPOLLHUP) && !driver_.lingering()) close();
    settle();
    // After the client's FIN, read on until the end is read: a read that returned its last
    // request did not take the end, and no new input will come to say it is there.
    return !closed_ && (events & (EPOLLIN | EPOLLRDHUP)) != 0 &&
           (driver_.input_may_remain() || (events & EPOLLRDHUP) != 0);
}

void TcpSession::settle() {
    if (closed_) return;
    if (driver_.closed()) {
        close();
        return;
    }
    std::uint32_t events = 0;
    if (driver_.wants_read()) events |= kInput;
    if (driver_.wants_write()) events |= EPOLLOUT;
    core_->poller->modify(fd_, events);
    arm_timer();
}

void TcpSession::arm_timer() {
    const auto at = driver_.deadline();
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
    driver_.on_time(Clock::now());
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
            self->driver_.answer_deferred(ticket, request, reply, bytes, Clock::now());
            self->settle();
        });
    };
}

void TcpSession::on_own_answer(const device::RequestContext& context,
                               std::span<const std::uint8_t> request,
                               protocol::ExceptionCode code) {
    const auto& options = core_->options;
    if (code == protocol::ExceptionCode::ServerDeviceBusy && options.on_busy_reply)
        options.on_busy_reply(context.unit);
    if (options.on_own_answer) options.on_own_answer(context, request, code);
}

}  // namespace mblab::server
