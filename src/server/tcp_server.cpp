#include "server/tcp_server.hpp"

#include "server/server_core.hpp"
#include "server/tcp_session.hpp"

namespace mblab::server {

TcpServer::TcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options)
    : TcpServer(io, handler, std::move(options),
                [](asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core) {
                    std::make_shared<TcpSession>(std::move(socket), std::move(core))->start();
                }) {}

TcpServer::TcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options,
                     SessionStarter start_session)
    : core_(std::make_shared<ServerCore>(handler, std::move(options))),
      start_session_(std::move(start_session)) {
    core_->listener = transport::TcpListener::create(
        io.get_executor(),
        transport::ListenerLimits{core_->options.max_connections, core_->options.allow});
    core_->poller = transport::SocketPoller::create(io.get_executor());
}

TcpServer::~TcpServer() {
    stop();
}

protocol::Result<std::uint16_t, std::string> TcpServer::start(
    const asio::ip::tcp::endpoint& endpoint) {
    auto port = core_->listener->listen(endpoint);
    if (!port) return port;
    std::weak_ptr<ServerCore> weak = core_;
    core_->listener->start([weak, start = start_session_](asio::ip::tcp::socket socket) {
        auto core = weak.lock();
        if (!core || core->stopped) return;
        start(std::move(socket), std::move(core));
    });
    return port;
}

void TcpServer::stop() {
    if (core_->stopped) return;
    core_->stopped = true;
    core_->listener->stop();
}

asio::ip::tcp::endpoint TcpServer::local_endpoint() const {
    return core_->listener->local_endpoint();
}

const ServerStats& TcpServer::stats() const {
    return core_->stats;
}

const transport::ListenerCounters& TcpServer::listener_counters() const {
    return core_->listener->counters();
}

}  // namespace mblab::server
