#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "device/request_handler.hpp"
#include "protocol/limits.hpp"
#include "server/serial_line_receiver.hpp"
#include "server/server_stats.hpp"
#include "transport/connection_table.hpp"
#include "transport/serial_url.hpp"

// The protocol of a server on one serial link (RTU or ASCII on a serial port, RTU over a TCP
// connection) without I/O: bytes, line faults and the clock in; answers, when each may go out
// (the turnaround) and whether to close out. The owner reads the link into input_space() while
// wants_input(), writes what output() gives and says when it went with sent(), wakes the core at
// deadline(), and closes once ending() says so; tests drive it with a manual clock.
namespace mblab::device {
class ReferenceDevice;
}

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
    // A character time when the line is paced (pace=1): the answer goes out one character per
    // character time, as from a UART, for ptys that would pass it on at once. 0: as written.
    std::chrono::nanoseconds pace{0};
    // A connection without a request for this long is closed; 0: never (serial lines).
    std::chrono::milliseconds idle_timeout{0};
    SerialLineHooks hooks;
    // Told why the link failed (a read or write error, not end of stream); may be empty.
    std::function<void(const std::string&)> on_failure;
};

// The setup of a server on a serial line at `url`'s settings: t3.5 from the baud rate (RTU) or
// the 1 s inter-character timeout (ASCII).
LineSetup serial_line_setup(const transport::SerialUrl& url, SerialLineHooks hooks);

// What carries the line's bytes. A serial port paces them itself (a long frame at a low baud
// rate takes seconds) and cannot be hung up on; a TCP client can trickle a frame and be closed.
enum class LineCarrier : std::uint8_t { SerialPort, Tcp };

// What the core takes from ServerOptions (whose allow list brings Asio in).
struct LineLimits {
    std::chrono::milliseconds partial_frame_timeout{250};
    std::chrono::milliseconds frame_limit{1000};  // TCP only: how long one frame may take
};

class LineSessionCore {
  public:
    static constexpr std::size_t kInputBytes = 512;

    LineSessionCore(device::RequestHandler& handler, const LineSetup& setup, LineCarrier carrier,
                    LineLimits limits, ServerStats& stats, LineClock::time_point now);
    LineSessionCore(const LineSessionCore&) = delete;
    LineSessionCore& operator=(const LineSessionCore&) = delete;

    // Whether to start a read: not while an answer is owed or bytes of the last read wait, as a
    // serial device takes one request at a time. A read already started may still complete.
    bool wants_input() const { return !ending_ && !answer_owed_ && !input_held_; }
    // Where to read into; it stays untouched until received().
    std::span<std::uint8_t> input_space() { return input_; }
    // `count` bytes were read into input_space() at `now`.
    void received(std::size_t count, LineClock::time_point now);
    // Copies `bytes` (at most kInputBytes) in and takes them, for owners without a buffer.
    void receive(std::span<const std::uint8_t> bytes, LineClock::time_point now);
    // Faults the port's driver counted below the bytes (FC 08 sub 12 and parity errors).
    void line_faults(std::uint32_t overruns, std::uint32_t parity_errors);
    // The TCP peer finished sending: what it left unfinished can no longer complete.
    void end_of_input();
    // The TCP client's address, handed to the handler with each request (RequestContext::peer);
    // a serial port has none.
    void set_peer(std::string peer) { peer_ = std::move(peer); }

    // The answer, once its turnaround and any delay are over; empty otherwise. Once given, it is
    // the owner's to write until sent().
    std::span<const std::uint8_t> output(LineClock::time_point now);
    // The answer output() gave is on the link.
    void sent(LineClock::time_point now);

    // When on_time() has something to do (a silence, the idle or frame limit, an answer's
    // turnaround); time_point::max() when nothing waits. It may come early.
    LineClock::time_point deadline() const;
    void on_time(LineClock::time_point now);
    // The connection is to be closed (idle, a frame too slow, end of input, a "close" fault).
    bool ending() const { return ending_; }

    transport::Standing standing(LineClock::time_point now) const;
    // The last whole request or answer sent.
    LineClock::time_point last_activity() const { return last_activity_; }
    bool has_partial() const { return receiver_.has_partial(); }

  private:
    // Takes the events of the bytes held until they are used up or an answer is owed.
    void process(LineClock::time_point now);
    void handle(const LineEvent& event, LineClock::time_point now);
    void owe_answer(std::uint8_t unit, std::size_t pdu_size, LineClock::time_point ready_at);

    device::RequestHandler& handler_;
    SerialLineHooks hooks_;
    LineFraming framing_;
    std::chrono::microseconds turnaround_;
    std::chrono::milliseconds idle_timeout_;
    LineCarrier carrier_;
    LineLimits limits_;
    ServerStats& stats_;
    SerialLineReceiver receiver_;
    std::string peer_;

    LineClock::time_point last_activity_;
    // The unfinished frame a TCP client is sending, since when (LineLimits::frame_limit).
    bool frame_open_ = false;
    LineClock::time_point frame_started_{};
    bool input_held_ = false;  // the receiver holds bytes whose events are not all taken
    bool answer_owed_ = false;
    bool answer_out_ = false;  // output() gave the answer; sent() not yet called
    LineClock::time_point answer_at_{};
    std::size_t answer_size_ = 0;
    bool ending_ = false;

    std::array<std::uint8_t, kInputBytes> input_{};
    std::array<std::uint8_t, protocol::limits::kMaxRtuAdu> response_{};
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> output_{};
};

}  // namespace mblab::server
