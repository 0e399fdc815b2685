#pragma once

#include <asio/io_context.hpp>
#include <functional>
#include <memory>
#include <string>

#include "device/request_handler.hpp"
#include "protocol/result.hpp"
#include "server/serial_session.hpp"
#include "server/server_stats.hpp"
#include "transport/serial_url.hpp"

// A device served on a serial line (RTU or ASCII) on a caller's io_context:
//
//   auto server = server::start_serial_server(io, device, *url, server::device_line_hooks(device));
//   if (!server) { print server.error(); exit 2; }
//   io.run();                       // until (*server)->stop()
//
// The handler is called on the io_context's thread only.
namespace mblab::server {

struct ServerCore;

class SerialServer {
  public:
    SerialServer(asio::io_context& io, device::RequestHandler& handler, SerialLineHooks hooks);
    ~SerialServer();
    SerialServer(const SerialServer&) = delete;
    SerialServer& operator=(const SerialServer&) = delete;

    // Opens the line at `url` (rtu:// or ascii://) and starts serving it. The error is one
    // line: a bad port, or "rtu+tcp:// is served by RtuTcpServer".
    protocol::Result<bool, std::string> start(const transport::SerialUrl& url);
    // Closes the line; the session ends once the io_context runs it. Idempotent.
    void stop();

    // Told why the line failed (a read or write error such as an unplugged adapter), once.
    void on_failure(std::function<void(const std::string&)> callback) {
        on_failure_ = std::move(callback);
    }
    const ServerStats& stats() const;

  private:
    asio::io_context& io_;
    SerialLineHooks hooks_;
    std::shared_ptr<ServerCore> core_;
    std::weak_ptr<LineSession<asio::serial_port>> session_;
    std::function<void(const std::string&)> on_failure_;
};

protocol::Result<std::unique_ptr<SerialServer>, std::string> start_serial_server(
    asio::io_context& io, device::RequestHandler& handler, const transport::SerialUrl& url,
    SerialLineHooks hooks = {});

}  // namespace mblab::server
