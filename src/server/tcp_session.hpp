#pragma once

#include <asio/any_io_executor.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <cstdint>
#include <memory>

#include "security/tls_channel.hpp"
#include "server/mbap_session.hpp"
#include "server/server_core.hpp"
#include "transport/connection_table.hpp"
#include "transport/socket_poller.hpp"

namespace mblab::server {

// One Modbus/TCP connection: the descriptor and its I/O around an MbapSession, which holds the
// protocol. The socket is read once each time the server's SocketPoller says it has data, the
// answers the session has ready go out in one send() or sendmsg(), output is watched only while
// the client leaves answers untaken, and one timer wakes the session at its deadline.
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
    void on_ready(std::uint32_t events) override;

  private:
    device::DeferredDone route_deferred(std::uint32_t ticket,
                                        const protocol::MbapHeader& request) override;
    void on_busy_reply(std::uint8_t unit) override;

    void read_ready(Clock::time_point now);
    bool wants_read() const;

    // Modbus/TCP Security: the socket carries a TLS session and the MBAP session sees plaintext.
    void read_tls(Clock::time_point now);
    // Moves the handshake on and hands decrypted bytes to the session while it takes input;
    // returns how many plaintext bytes it handed over.
    std::size_t pump_tls(Clock::time_point now);
    void on_handshake();
    void refuse_handshake(const std::string& reason);
    // Counts and logs a client refused after its handshake, then ends its session.
    void refuse_client(const std::string& reason);
    // What TLS has for the network; false when the socket is full (or gone).
    bool send_cipher();
    void flush_tls(Clock::time_point now);
    void end_input(Clock::time_point now);
    // Sends what the session has ready until the socket is full or nothing is ready, then
    // closes if the session is done.
    void flush(Clock::time_point now);
    // After an event: the watched events and the timer brought up to date.
    void settle();
    void arm_timer();
    void on_timer();
    void shutdown_and_close();
    // Gives the connection's place in the listener's table back (once).
    void leave_table();
    // Stops watching the socket and closes it (once).
    void close_socket();

    asio::any_io_executor executor_;
    int fd_ = -1;
    std::shared_ptr<ServerCore> core_;
    MbapSession session_;
    asio::steady_timer timer_;
    // When the timer wakes; a later session deadline waits for that wake-up, which costs less
    // than setting the timer again on every request.
    Clock::time_point timer_at_ = Clock::time_point::max();
    bool timer_pending_ = false;
    bool closed_ = false;
    bool in_table_ = false;
    bool write_blocked_ = false;   // the socket took less than it was given
    bool input_ended_ = false;     // the session was told the client sends nothing more
    bool seen_plaintext_ = false;  // the first plaintext was checked for a bare PDU
    std::unique_ptr<security::TlsChannel> tls_;
    Clock::time_point handshake_deadline_ = Clock::time_point::max();
};

}  // namespace mblab::server
