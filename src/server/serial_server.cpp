#include "server/serial_server.hpp"

#include "server/server_core.hpp"
#include "transport/serial_port.hpp"

namespace mblab::server {

SerialServer::SerialServer(asio::io_context& io, device::RequestHandler& handler,
                           SerialLineHooks hooks)
    : io_(io),
      hooks_(std::move(hooks)),
      core_(std::make_shared<ServerCore>(handler, ServerOptions{})) {}

SerialServer::~SerialServer() {
    stop();
}

protocol::Result<bool, std::string> SerialServer::start(const transport::SerialUrl& url) {
    if (url.kind == transport::SerialUrl::Kind::RtuOverTcp) {
        return std::string("rtu+tcp:// is a TCP listener, not a serial line");
    }
    if (!session_.expired()) return std::string("the serial server is already running");
    auto port = transport::open_serial_port(io_.get_executor(), url.line);
    if (!port) return port.error();
    auto setup = serial_line_setup(url, hooks_);
    setup.on_failure = [this, device = url.line.device](const std::string& why) {
        if (on_failure_) on_failure_("serial line " + device + " failed: " + why);
    };
    auto session = std::make_shared<LineSession<asio::serial_port>>(std::move(port.value()), core_,
                                                                    std::move(setup));
    session->start();
    session_ = session;
    return true;
}

void SerialServer::stop() {
    if (auto session = session_.lock()) session->close();
    session_.reset();
}

const ServerStats& SerialServer::stats() const {
    return core_->stats;
}

protocol::Result<std::unique_ptr<SerialServer>, std::string> start_serial_server(
    asio::io_context& io, device::RequestHandler& handler, const transport::SerialUrl& url,
    SerialLineHooks hooks) {
    auto server = std::make_unique<SerialServer>(io, handler, std::move(hooks));
    auto started = server->start(url);
    if (!started) return started.error();
    return server;
}

}  // namespace mblab::server
