#pragma once

#include <asio/ip/tcp.hpp>
#include <asio/serial_port.hpp>
#include <asio/steady_timer.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "server/line_session_core.hpp"
#include "server/server_core.hpp"
#include "transport/connection_table.hpp"
#include "transport/linger.hpp"
#include "transport/serial_port.hpp"

namespace mblab::server {

// Why a serial line failed, as the server reports it. A line that goes away (a USB adapter
// unplugged, the far end of a pty closed) shows as end of file or as EIO, whichever the kernel
// reports first; both read "the line hung up".
std::string line_failure_text(const asio::error_code& ec);

// One serial link carrying RTU or ASCII frames: a serial port, or a TCP connection with RTU
// frames. The link's I/O around a LineSessionCore, which holds the protocol: a read is
// outstanding while the core takes input, its answer is written once the core gives it, and one
// timer wakes the core at its deadline. Asio callbacks on the io_context's thread.
template <class Stream>
class LineSession final : public std::enable_shared_from_this<LineSession<Stream>>,
                          public transport::TrackedConnection {
  public:
    LineSession(Stream stream, std::shared_ptr<ServerCore> core, LineSetup setup);
    ~LineSession();

    // Registers with the listener's connection table (when there is one) and starts reading.
    void start();

    transport::Standing standing(LineClock::time_point now) const override;
    LineClock::time_point last_activity() const override { return line_.last_activity(); }
    void close() override;

  private:
    // After any event: the core woken, its answer written, a read started and the timer set as
    // it says.
    void settle();
    // The core ended the connection. A TCP connection ends its output, then reads and drops what
    // the client still sends (transport::Linger) before it closes, so that no input left unread
    // makes the kernel reset it under the answers the client has not read yet.
    void end();
    void discarded(const asio::error_code& ec);
    void read();
    void write(std::span<const std::uint8_t> answer);
    // Writes answer[index] (and any later character already due) once `start` + index + 1
    // character times have passed, then the rest.
    void write_paced(std::span<const std::uint8_t> answer, std::size_t index,
                     LineClock::time_point start);
    void written(const asio::error_code& ec);
    void arm_timer(LineClock::time_point at);
    void count_line_faults();
    void fail(const std::string& why);
    // Gives the connection's place in the listener's table back (once).
    void leave_table();

    Stream stream_;
    std::shared_ptr<ServerCore> core_;
    std::function<void(const std::string&)> on_failure_;
    LineSessionCore line_;
    std::optional<transport::SerialFaultMonitor> faults_;
    asio::steady_timer timer_;
    std::chrono::nanoseconds pace_;
    asio::steady_timer pace_timer_;
    LineClock::time_point timer_at_ = LineClock::time_point::max();
    transport::Linger linger_;
    bool closed_ = false;
    bool input_ended_ = false;  // the TCP client sent its FIN
    bool in_table_ = false;
    bool reading_ = false;
    bool writing_ = false;
};

extern template class LineSession<asio::serial_port>;
extern template class LineSession<asio::ip::tcp::socket>;

}  // namespace mblab::server
