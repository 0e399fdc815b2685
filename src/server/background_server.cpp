#include "server/background_server.hpp"

#include <asio/post.hpp>

namespace mblab::server {

BackgroundServer::BackgroundServer(device::RequestHandler& handler, ServerOptions options)
    : io_(1), server_(io_, handler, std::move(options)) {}

BackgroundServer::~BackgroundServer() {
    stop();
}

protocol::Result<std::uint16_t, std::string> BackgroundServer::start(
    const asio::ip::tcp::endpoint& endpoint) {
    if (thread_.joinable()) return std::string("the background server is already running");
    auto port = server_.start(endpoint);
    if (!port) return port;
    port_ = *port;
    work_.emplace(io_.get_executor());
    thread_ = std::thread([this] { io_.run(); });
    return port;
}

void BackgroundServer::stop() {
    if (!thread_.joinable()) return;
    // Closing the listener, sockets and timers on the server's thread leaves the io_context
    // nothing to wait for, after which run() returns by itself.
    asio::post(io_, [this] {
        server_.stop();
        work_.reset();
    });
    thread_.join();
}

}  // namespace mblab::server
