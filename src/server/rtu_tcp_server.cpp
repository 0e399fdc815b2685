#include "server/rtu_tcp_server.hpp"

#include "server/server_core.hpp"

namespace mblab::server {

RtuTcpServer::RtuTcpServer(asio::io_context& io, device::RequestHandler& handler,
                           ServerOptions options, SerialLineHooks hooks)
    : core_(std::make_shared<ServerCore>(handler, std::move(options))) {
    core_->listener = transport::TcpListener::create(
        io.get_executor(),
        transport::ListenerLimits{core_->options.max_connections, core_->options.allow});
    setup_.framing = LineFraming::Rtu;
    setup_.unknown_length = protocol::RtuFramer::UnknownLength::EndOnCrcMatch;
    setup_.timing.silence = core_->options.partial_frame_timeout;
    setup_.idle_timeout = core_->options.idle_timeout;
    setup_.hooks = std::move(hooks);
}

RtuTcpServer::~RtuTcpServer() {
    stop();
}

protocol::Result<std::uint16_t, std::string> RtuTcpServer::start(
    const asio::ip::tcp::endpoint& endpoint) {
    auto port = core_->listener->listen(endpoint);
    if (!port) return port;
    std::weak_ptr<ServerCore> weak = core_;
    core_->listener->start([weak, setup = setup_](asio::ip::tcp::socket socket) {
        auto core = weak.lock();
        if (!core || core->stopped) return;
        std::make_shared<LineSession<asio::ip::tcp::socket>>(std::move(socket), core, setup)
            ->start();
    });
    return port;
}

void RtuTcpServer::stop() {
    if (core_->stopped) return;
    core_->stopped = true;
    core_->listener->stop();
}

asio::ip::tcp::endpoint RtuTcpServer::local_endpoint() const {
    return core_->listener->local_endpoint();
}

const ServerStats& RtuTcpServer::stats() const {
    return core_->stats;
}

const transport::ListenerCounters& RtuTcpServer::listener_counters() const {
    return core_->listener->counters();
}

}  // namespace mblab::server
