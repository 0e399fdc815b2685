#pragma once

#include <array>
#include <asio/awaitable.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/serial_port.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "device/reference_device.hpp"
#include "protocol/limits.hpp"
#include "server/serial_line_receiver.hpp"
#include "server/server_core.hpp"
#include "transport/connection_table.hpp"
#include "transport/serial_port.hpp"

namespace mblab::server {

// What a line tells the device behind it besides requests: the FC 08 counters count frames
// that never reach it, and ASCII framing follows the delimiter FC 08 sub 03 set. Each may be
// empty. Called on the session's thread.
struct SerialLineHooks {
    std::function<void(LineError)> on_frame_error;
    std::function<void()> on_overrun;
    std::function<void()> on_parity_error;
    std::function<std::uint8_t(std::uint8_t unit)> ascii_delimiter;
};

// Hooks that feed the reference device's counters (FC 08 sub 0C, 12) and ASCII delimiter.
SerialLineHooks device_line_hooks(device::ReferenceDevice& device);

struct LineSetup {
    LineFraming framing = LineFraming::Rtu;
    LineTiming timing;
    protocol::RtuFramer::UnknownLength unknown_length =
        protocol::RtuFramer::UnknownLength::AwaitSilence;
    // Silence kept between a request's last byte and the answer (RTU on a line: t3.5).
    std::chrono::microseconds turnaround{0};
    // A connection without a request for this long is closed; 0: never (serial lines).
    std::chrono::milliseconds idle_timeout{0};
    SerialLineHooks hooks;
    // Told why the link failed (a read or write error, not end of stream); may be empty.
    std::function<void(const std::string&)> on_failure;
};

// Why a serial line failed, as the server reports it. A line that goes away (a USB adapter
// unplugged, the far end of a pty closed) shows as end of file or as EIO, whichever the kernel
// reports first; both read "the line hung up".
std::string line_failure_text(const asio::error_code& ec);

// The setup of a server on a serial line at `url`'s settings: t3.5 from the baud rate (RTU) or
// the 1 s inter-character timeout (ASCII).
LineSetup serial_line_setup(const transport::SerialUrl& url, SerialLineHooks hooks);

// One serial link carrying RTU or ASCII frames: a serial port, or a TCP connection with RTU
// frames. A reader coroutine frames what arrives, asks the device and writes the answer, one
// request at a time as a serial master sends them; a watchdog coroutine interrupts the read
// when silence ends a frame (t3.5, the ASCII timeout) or the connection idles out.
template <class Stream>
class LineSession final : public std::enable_shared_from_this<LineSession<Stream>>,
                          public transport::TrackedConnection {
  public:
    LineSession(Stream stream, std::shared_ptr<ServerCore> core, LineSetup setup);
    ~LineSession();

    // Registers with the listener's connection table (when there is one) and starts the loops.
    void start();

    transport::Standing standing(LineClock::time_point now) const override;
    LineClock::time_point last_activity() const override { return last_activity_; }
    void close() override;

  private:
    using Self = std::shared_ptr<LineSession>;

    asio::awaitable<void> read_loop(Self self);
    asio::awaitable<void> watchdog_loop(Self self);
    asio::awaitable<void> handle(const LineEvent& event);
    asio::awaitable<void> answer(std::uint8_t unit, std::size_t pdu_size,
                                 LineClock::time_point ready_at);
    LineClock::time_point next_deadline() const;
    void count_line_faults();
    void fail(const std::string& why);
    // Gives the connection's place in the listener's table back (once).
    void leave_table();

    Stream stream_;
    std::shared_ptr<ServerCore> core_;
    LineSetup setup_;
    SerialLineReceiver receiver_;
    std::optional<transport::SerialFaultMonitor> faults_;
    asio::steady_timer watchdog_timer_;
    asio::steady_timer delay_timer_;
    LineClock::time_point last_activity_;
    // The unfinished frame a TCP client is sending, since when (for ServerOptions::frame_limit).
    bool frame_open_ = false;
    LineClock::time_point frame_started_{};
    bool closed_ = false;
    bool in_table_ = false;
    bool reading_ = false;  // a read is outstanding: the watchdog may interrupt it

    std::array<std::uint8_t, 512> input_{};
    std::array<std::uint8_t, protocol::limits::kMaxRtuAdu> response_{};
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> output_{};
};

extern template class LineSession<asio::serial_port>;
extern template class LineSession<asio::ip::tcp::socket>;

}  // namespace mblab::server
