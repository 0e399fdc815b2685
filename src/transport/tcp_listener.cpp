#include "transport/tcp_listener.hpp"

#include <fcntl.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <chrono>

namespace mblab::transport {

namespace {

constexpr auto kAcceptRetryDelay = std::chrono::milliseconds(50);
constexpr auto use_tuple = asio::experimental::as_tuple(asio::use_awaitable);

// Programs this process starts (tests run the mblab binary beside an in-process server) must not
// inherit the listener or its connections: an inherited copy would keep a port bound, or a
// connection the server closed open.
void close_on_exec(int fd) {
    const int flags = ::fcntl(fd, F_GETFD);
    if (flags >= 0) ::fcntl(fd, F_SETFD, flags | FD_CLOEXEC);
}

// An RST rather than a FIN tells a refused client at once that nobody will answer.
void reset_connection(asio::ip::tcp::socket& socket) {
    asio::error_code ignored;
    socket.set_option(asio::socket_base::linger(true, 0), ignored);
    socket.close(ignored);
}

asio::awaitable<void> accept_loop(std::shared_ptr<TcpListener> self,
                                  asio::ip::tcp::acceptor& acceptor,
                                  std::function<bool(asio::ip::tcp::socket&)> admit,
                                  TcpListener::AdmitHandler on_admitted) {
    asio::steady_timer backoff(acceptor.get_executor());
    while (acceptor.is_open()) {
        auto [ec, socket] = co_await acceptor.async_accept(use_tuple);
        if (ec == asio::error::operation_aborted || !acceptor.is_open()) break;
        if (ec) {
            // Out of descriptors or a connection reset before accept: retry later, don't spin.
            backoff.expires_after(kAcceptRetryDelay);
            co_await backoff.async_wait(use_tuple);
            continue;
        }
        close_on_exec(socket.native_handle());
        if (admit(socket)) on_admitted(std::move(socket));
    }
    (void)self;
}

}  // namespace

std::shared_ptr<TcpListener> TcpListener::create(asio::any_io_executor executor,
                                                 ListenerLimits limits) {
    return std::shared_ptr<TcpListener>(new TcpListener(std::move(executor), std::move(limits)));
}

TcpListener::TcpListener(asio::any_io_executor executor, ListenerLimits limits)
    : acceptor_(std::move(executor)), limits_(std::move(limits)) {}

protocol::Result<std::uint16_t, std::string> TcpListener::listen(
    const asio::ip::tcp::endpoint& endpoint) {
    asio::error_code ec;
    auto fail = [&](const char* step) {
        asio::error_code ignored;
        acceptor_.close(ignored);
        return std::string("cannot ") + step + " " + endpoint.address().to_string() + ":" +
               std::to_string(endpoint.port()) + ": " + ec.message();
    };
    acceptor_.open(endpoint.protocol(), ec);
    if (ec) return fail("open a socket for");
    close_on_exec(acceptor_.native_handle());
    acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
    if (ec) return fail("configure a socket for");
    acceptor_.bind(endpoint, ec);
    if (ec) return fail("listen on");
    acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) return fail("listen on");
    return acceptor_.local_endpoint().port();
}

void TcpListener::start(AdmitHandler on_admitted) {
    auto self = shared_from_this();
    asio::co_spawn(acceptor_.get_executor(),
                   accept_loop(
                       self, acceptor_, [this](asio::ip::tcp::socket& s) { return admit(s); },
                       std::move(on_admitted)),
                   asio::detached);
}

void TcpListener::stop() {
    asio::error_code ignored;
    acceptor_.close(ignored);
    connections_.close_all();
}

asio::ip::tcp::endpoint TcpListener::local_endpoint() const {
    asio::error_code ignored;
    return acceptor_.local_endpoint(ignored);
}

bool TcpListener::admit(asio::ip::tcp::socket& socket) {
    asio::error_code ec;
    auto peer = socket.remote_endpoint(ec);
    if (ec) return false;  // already gone
    if (!limits_.allow.allows(peer.address())) {
        counters_.refused_address.fetch_add(1, std::memory_order_relaxed);
        reset_connection(socket);
        return false;
    }
    if (limits_.max_connections != 0 && connections_.size() >= limits_.max_connections) {
        switch (connections_.close_one_for_newcomer(Clock::now())) {
            case Standing::Busy:
                counters_.refused_full.fetch_add(1, std::memory_order_relaxed);
                reset_connection(socket);
                return false;
            case Standing::Idle:
            case Standing::Unused:
            case Standing::Ending:
                counters_.evicted_idle.fetch_add(1, std::memory_order_relaxed);
                break;
            case Standing::Stalled:
                counters_.evicted_stalled.fetch_add(1, std::memory_order_relaxed);
                break;
            case Standing::Handshaking:
                counters_.evicted_handshaking.fetch_add(1, std::memory_order_relaxed);
                break;
        }
    }
    counters_.accepted.fetch_add(1, std::memory_order_relaxed);
    socket.set_option(asio::ip::tcp::no_delay(true), ec);
    return true;
}

}  // namespace mblab::transport
