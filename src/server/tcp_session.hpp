#pragma once

#include <asio/any_io_executor.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <cstdint>
#include <memory>

#include "server/mbap_driver.hpp"
#include "server/mbap_session.hpp"
#include "server/server_core.hpp"
#include "transport/channel.hpp"
#include "transport/connection_table.hpp"
#include "transport/socket_channel.hpp"
#include "transport/socket_poller.hpp"
#include "transport/tls_stream.hpp"

namespace mblab::server {

// One Modbus/TCP connection: the descriptor, its channel (the socket, or TLS over it) and an
// MbapDriver that moves bytes and time between the channel and an MbapSession, which holds the
// protocol. The socket is read once each time the server's SocketPoller says it has data, the
// answers the session has ready go out in one send() or sendmsg(), output is watched only while
// the client leaves answers untaken, and one timer wakes the driver at its deadline.
class TcpSession final : public std::enable_shared_from_this<TcpSession>,
                         public transport::TrackedConnection,
                         public transport::SocketPoller::Watcher,
                         private MbapSession::Host {
  public:
    // Takes the socket's descriptor over from Asio.
    TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core);
    ~TcpSession();

    // Registers with the listener's connection table and the poller, and arms the timer.
    void start();

    transport::Standing standing(Clock::time_point now) const override;
    Clock::time_point last_activity() const override { return session_.last_activity(); }
    void close() override;
    bool on_ready(std::uint32_t events) override;

  private:
    device::DeferredDone route_deferred(std::uint32_t ticket,
                                        const protocol::MbapHeader& request) override;
    void on_own_answer(const device::RequestContext& context, std::span<const std::uint8_t> request,
                       protocol::ExceptionCode code) override;

    // After an event: the connection closed if the driver is done, else the watched events and
    // the timer brought up to date.
    void settle();
    void arm_timer();
    void on_timer();
    // Gives the connection's place in the listener's table back (once).
    void leave_table();
    // Stops watching the socket and closes it (once).
    void close_socket();

    asio::any_io_executor executor_;
    int fd_ = -1;
    std::shared_ptr<ServerCore> core_;
    // Kept in the session, not behind a pointer of its own: the driver reaches it on every
    // request.
    transport::SocketChannel socket_;
    std::unique_ptr<transport::TlsStream> tls_;  // Modbus/TCP Security: TLS over socket_
    // The socket, or TLS over it: the driver's only way to the client.
    transport::Channel& channel_;
    MbapSession session_;
    MbapDriver driver_;
    asio::steady_timer timer_;
    // When the timer wakes; a later session deadline waits for that wake-up, which costs less
    // than setting the timer again on every request.
    Clock::time_point timer_at_ = Clock::time_point::max();
    bool timer_pending_ = false;
    bool closed_ = false;
    bool in_table_ = false;
};

}  // namespace mblab::server
