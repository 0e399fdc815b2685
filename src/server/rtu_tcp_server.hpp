#pragma once

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "device/request_handler.hpp"
#include "protocol/result.hpp"
#include "server/serial_session.hpp"
#include "server/server_options.hpp"
#include "server/server_stats.hpp"
#include "transport/tcp_listener.hpp"

// RTU frames (address, PDU, CRC; no MBAP header) over TCP connections, as serial device
// servers and some gateways speak them. Requests are served with serial addressing (0 is a
// broadcast), one at a time per connection. A TCP stream has no silence to end frames, so a
// frame of unknown layout ends where its CRC first matches; an unfinished frame is dropped
// after options.partial_frame_timeout. The connection limits, allow-list and idle timeout of
// ServerOptions apply as for Modbus/TCP. Run the io_context on one thread.
namespace mblab::server {

struct ServerCore;

class RtuTcpServer {
  public:
    RtuTcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options,
                 SerialLineHooks hooks = {});
    ~RtuTcpServer();
    RtuTcpServer(const RtuTcpServer&) = delete;
    RtuTcpServer& operator=(const RtuTcpServer&) = delete;

    // Binds and starts accepting; returns the bound port (an ephemeral one for port 0).
    protocol::Result<std::uint16_t, std::string> start(const asio::ip::tcp::endpoint& endpoint);
    // Stops accepting and closes every connection; idempotent.
    void stop();

    asio::ip::tcp::endpoint local_endpoint() const;
    const ServerStats& stats() const;
    const transport::ListenerCounters& listener_counters() const;

  private:
    std::shared_ptr<ServerCore> core_;
    LineSetup setup_;
};

}  // namespace mblab::server
