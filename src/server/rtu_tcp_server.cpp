#include "server/rtu_tcp_server.hpp"

#include <memory>

#include "server/server_core.hpp"

namespace mblab::server {

TcpServer::SessionStarter rtu_session_starter(const ServerOptions& options, SerialLineHooks hooks) {
    LineSetup setup;
    setup.framing = LineFraming::Rtu;
    setup.unknown_length = protocol::RtuFramer::UnknownLength::EndOnCrcMatch;
    setup.timing.silence = options.partial_frame_timeout;
    setup.idle_timeout = options.idle_timeout;
    setup.hooks = std::move(hooks);
    return
        [setup = std::move(setup)](asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core) {
            std::make_shared<LineSession<asio::ip::tcp::socket>>(std::move(socket), std::move(core),
                                                                 setup)
                ->start();
        };
}

}  // namespace mblab::server
