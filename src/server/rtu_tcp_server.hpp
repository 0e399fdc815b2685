#pragma once

#include <asio/io_context.hpp>

#include "device/request_handler.hpp"
#include "server/serial_session.hpp"
#include "server/server_options.hpp"
#include "server/tcp_server.hpp"

// RTU frames (address, PDU, CRC; no MBAP header) over TCP connections, as serial device
// servers and some gateways speak them: a TcpServer whose sessions frame RTU. Requests are
// served with serial addressing (0 is a broadcast), one at a time per connection. A TCP stream
// has no silence to end frames, so a frame of unknown layout ends where its CRC first matches;
// an unfinished frame is dropped after options.partial_frame_timeout. The connection limits,
// allow-list and idle timeout of ServerOptions apply as for Modbus/TCP.
namespace mblab::server {

// Sessions that frame RTU, for any TcpServer:
//   TcpServer server(io, device, options, rtu_session_starter(options, hooks));
TcpServer::SessionStarter rtu_session_starter(const ServerOptions& options,
                                              SerialLineHooks hooks = {});

class RtuTcpServer final : public TcpServer {
  public:
    RtuTcpServer(asio::io_context& io, device::RequestHandler& handler, ServerOptions options,
                 SerialLineHooks hooks = {})
        : TcpServer(io, handler, options, rtu_session_starter(options, std::move(hooks))) {}
};

}  // namespace mblab::server
