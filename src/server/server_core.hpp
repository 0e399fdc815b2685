#pragma once

#include <memory>

#include "device/request_handler.hpp"
#include "server/server_options.hpp"
#include "server/server_stats.hpp"
#include "transport/socket_poller.hpp"
#include "transport/tcp_listener.hpp"

namespace mblab::server {

// What one server's sessions share. Sessions hold it by shared_ptr, so a session that outlives
// its TcpServer object (its io_context still holds it) never touches freed state.
struct ServerCore {
    ServerCore(device::RequestHandler& handler_in, ServerOptions options_in)
        : handler(handler_in), options(std::move(options_in)) {}

    device::RequestHandler& handler;
    const ServerOptions options;
    ServerStats stats;
    std::shared_ptr<transport::TcpListener> listener;
    std::shared_ptr<transport::SocketPoller> poller;  // the Modbus/TCP sessions' sockets
    bool stopped = false;
};

}  // namespace mblab::server
