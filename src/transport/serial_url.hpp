#pragma once

#include <asio/ip/tcp.hpp>
#include <bitset>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "protocol/result.hpp"

// Addresses of serial Modbus links:
//   rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1&data=8   RTU on a serial line
//   ascii:///dev/ttyUSB0?baud=9600&parity=E&data=7         ASCII on a serial line
//   rtu+tcp://127.0.0.1:502                                RTU frames over a TCP connection
// strict=1 makes a served RTU line drop frames with a gap over t1.5 inside them [SER 2.5.1.1]
// (off by default: USB adapters deliver frames in packets with such gaps). pace=1 makes this side
// send one character per character time, as a UART does, so that two ends of a pty (which passes
// bytes on at once) keep a real line's timing. A line given to a
// gateway also takes timeout=MS (how long a device may take to answer) and units=1-10,20 (the
// unit ids routed to the line).
namespace mblab::transport {

enum class Parity : std::uint8_t { None, Even, Odd };

// [SER] 2.5: 19200 baud, even parity, one stop bit; 8 data bits for RTU, 7 for ASCII.
struct SerialSettings {
    std::string device;
    unsigned baud = 19200;
    std::uint8_t data_bits = 8;
    Parity parity = Parity::Even;
    std::uint8_t stop_bits = 1;
};

struct SerialUrl {
    enum class Kind : std::uint8_t { Rtu, Ascii, RtuOverTcp };
    Kind kind = Kind::Rtu;
    SerialSettings line;               // Rtu, Ascii
    asio::ip::tcp::endpoint endpoint;  // RtuOverTcp
    bool strict_timing = false;        // RTU: enforce t1.5 inside frames
    bool paced = false;                // send at the baud rate (pace=1)
    std::chrono::milliseconds response_timeout{1000};
    std::bitset<256> units;  // unit ids a gateway routes here; 1..247 unless units= is given
};

// True for rtu:, ascii: and rtu+tcp: addresses, so a caller can tell them from tcp:// ones.
bool is_serial_url(std::string_view url);

// The error is one line naming what is wrong and showing the expected form, e.g.
// "bad address 'rtu:///dev/ttyS0?parity=X': parity must be N, E or O (expected ...)".
protocol::Result<SerialUrl, std::string> parse_serial_url(std::string_view url);

// A serial line's settings alone, as a URL's query gives them ("baud=9600&parity=N&stop=2"):
// what is wrong with them in a few words, or nothing. Only baud, parity, stop and data.
std::optional<std::string> line_settings_error(std::string_view settings);

// `url` with `settings` (checked by line_settings_error) put over its line's.
SerialUrl with_line_settings(SerialUrl url, std::string_view settings);

// The URL with every setting spelled out: "rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1&data=8".
std::string format_serial_url(const SerialUrl& url);

}  // namespace mblab::transport
