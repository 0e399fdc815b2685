#pragma once

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "device/request_handler.hpp"
#include "protocol/result.hpp"
#include "server/server_options.hpp"
#include "server/server_stats.hpp"
#include "transport/tcp_listener.hpp"

// A Modbus/TCP server on a caller's io_context: the listener accepts, and each connection is a
// TcpSession the SocketPoller wakes when its socket is ready; the handler is called on the
// io_context's thread only (a device need not be thread-safe). Run the io_context on one thread.
namespace mblab::server {

struct ServerCore;

class TcpServer {
  public:
    // Starts the session of one admitted connection: how another framing (RTU over TCP, say)
    // reuses the listener, limits and lifetime rules of this server.
    using SessionStarter =
        std::function<void(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core)>;

    // Modbus/TCP (MBAP) sessions. `handler` must outlive every run of the io_context that may
    // still serve a connection.
    TcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options);
    TcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options,
              SessionStarter start_session);
    ~TcpServer();
    TcpServer(const TcpServer&) = delete;
    TcpServer& operator=(const TcpServer&) = delete;

    // Binds and starts accepting; returns the bound port (an ephemeral one for port 0) or an
    // error such as "cannot listen on 127.0.0.1:502: Address already in use".
    protocol::Result<std::uint16_t, std::string> start(const asio::ip::tcp::endpoint& endpoint);
    // Stops accepting and closes every connection. Call on the io_context's thread (or while
    // it does not run); idempotent.
    void stop();

    asio::ip::tcp::endpoint local_endpoint() const;
    const ServerStats& stats() const;
    const transport::ListenerCounters& listener_counters() const;

  private:
    std::shared_ptr<ServerCore> core_;
    SessionStarter start_session_;
};

}  // namespace mblab::server
