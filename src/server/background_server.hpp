#pragma once

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "device/request_handler.hpp"
#include "protocol/result.hpp"
#include "server/server_options.hpp"
#include "server/tcp_server.hpp"

// A TcpServer on its own io_context and thread, for code that wants a device to talk to in
// the same process (the conformance tester with no target, tests):
//
//   BackgroundServer server(device);
//   auto port = server.start();          // 127.0.0.1, an ephemeral port
//   ... connect to 127.0.0.1:*port ...
//   server.stop();                       // or let the destructor do it
//
// The handler is called on the server's thread only, and must outlive stop().
namespace mblab::server {

class BackgroundServer {
  public:
    explicit BackgroundServer(device::RequestHandler& handler, ServerOptions options = {});
    ~BackgroundServer();
    BackgroundServer(const BackgroundServer&) = delete;
    BackgroundServer& operator=(const BackgroundServer&) = delete;

    // Binds, then starts the thread. Returns the bound port.
    protocol::Result<std::uint16_t, std::string> start(const asio::ip::tcp::endpoint& endpoint = {
                                                           asio::ip::address_v4::loopback(), 0});
    // Closes every connection and joins the thread; idempotent.
    void stop();

    std::uint16_t port() const { return port_; }
    // Read them from any thread.
    const ServerStats& stats() const { return server_.stats(); }
    const transport::ListenerCounters& listener_counters() const {
        return server_.listener_counters();
    }

  private:
    asio::io_context io_;
    TcpServer server_;
    std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work_;
    std::thread thread_;
    std::uint16_t port_ = 0;
};

}  // namespace mblab::server
