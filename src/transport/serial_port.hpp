#pragma once

#include <asio/any_io_executor.hpp>
#include <asio/serial_port.hpp>
#include <chrono>
#include <cstdint>
#include <string>

#include "protocol/result.hpp"
#include "transport/serial_url.hpp"

namespace mblab::transport {

// RTU's silent intervals [SER 2.5.1.1]: a character is 11 bits; t1.5 and t3.5 follow the baud
// rate up to 19200 and are fixed at 750 us and 1750 us above it.
struct CharTimes {
    std::chrono::microseconds t15;
    std::chrono::microseconds t35;
};
CharTimes rtu_char_times(unsigned baud);

// One character's time on the line as set: a start bit, the data bits, the parity bit if any and
// the stop bits, at the baud rate [SER 2.5.1, 2.5.2].
std::chrono::nanoseconds character_time(const SerialSettings& settings);

// Whether `device` is a pseudo-terminal (a /dev/pts end, as tests and socat use): it passes
// bytes on as they are written, never at the baud rate, so line timing through it is logical.
bool is_pseudo_terminal(const std::string& device);

// Opens the device raw (no echo, no line editing, no flow control) with the settings' baud
// rate, data bits, parity and stop bits. The error names the device, the cause and the fix,
// e.g. "cannot open serial port /dev/ttyUSB0: Permission denied (add your user to the dialout
// group)".
protocol::Result<asio::serial_port, std::string> open_serial_port(asio::any_io_executor executor,
                                                                  const SerialSettings& settings);

// Line faults the driver counts below the bytes we read: hardware and buffer overruns (FC 08
// sub 12) and characters with a parity or framing error (the kernel hands those on as 0x00 or
// drops them, so the frame then fails its check too). Drivers that count nothing (ptys, some
// USB adapters) report no faults.
class SerialFaultMonitor {
  public:
    struct Faults {
        std::uint32_t overruns = 0;
        std::uint32_t parity_errors = 0;
    };

    explicit SerialFaultMonitor(int fd);
    // The faults counted since the last call (or since construction).
    Faults poll();

  private:
    bool read_counts(Faults& counts) const;

    int fd_;
    bool supported_ = false;
    Faults last_{};
};

}  // namespace mblab::transport
