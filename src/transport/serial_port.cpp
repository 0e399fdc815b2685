#include "transport/serial_port.hpp"

#include <linux/serial.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <cerrno>

namespace mblab::transport {

namespace {

constexpr unsigned kBitsPerChar = 11;
constexpr unsigned kFixedTimingAbove = 19200;

std::chrono::microseconds char_time_multiple(unsigned tenths_of_chars, unsigned baud) {
    // tenths * 11 bits * 1e6 us / (10 * baud), rounded up so a deadline is never early.
    const std::uint64_t numerator = std::uint64_t{tenths_of_chars} * kBitsPerChar * 100'000;
    return std::chrono::microseconds((numerator + baud - 1) / baud);
}

std::string open_error(const SerialSettings& settings, const asio::error_code& ec,
                       const std::string& what) {
    std::string out = "cannot " + what;
    out += " serial port " + settings.device + ": " + ec.message();
    // Asio's system category does not compare equal to std::errc values: test the errno.
    switch (ec.value()) {
        case ENOENT:
        case ENODEV:
        case ENXIO:
            out += " (check the device path, e.g. ls /dev/ttyUSB* /dev/ttyACM*)";
            break;
        case EACCES:
            out += " (add your user to the dialout group, or run with access to the device)";
            break;
        case EBUSY:
            out += " (another program holds the port)";
            break;
        default:
            break;
    }
    return out;
}

asio::serial_port::parity::type parity_option(Parity parity) {
    switch (parity) {
        case Parity::Even:
            return asio::serial_port::parity::even;
        case Parity::Odd:
            return asio::serial_port::parity::odd;
        case Parity::None:
            break;
    }
    return asio::serial_port::parity::none;
}

}  // namespace

CharTimes rtu_char_times(unsigned baud) {
    using std::chrono::microseconds;
    if (baud == 0 || baud > kFixedTimingAbove) return {microseconds(750), microseconds(1750)};
    return {char_time_multiple(15, baud), char_time_multiple(35, baud)};
}

std::chrono::nanoseconds character_time(const SerialSettings& settings) {
    const unsigned bits =
        1U + settings.data_bits + (settings.parity == Parity::None ? 0U : 1U) + settings.stop_bits;
    const unsigned baud = settings.baud == 0 ? 19200U : settings.baud;
    return std::chrono::nanoseconds(1'000'000'000ULL * bits / baud);
}

bool is_pseudo_terminal(const std::string& device) {
    struct stat info {};
    if (::stat(device.c_str(), &info) != 0 || !S_ISCHR(info.st_mode)) return false;
    // Unix98 pty slaves take majors 136..143 (Linux's Documentation/admin-guide/devices.txt).
    const unsigned kind = major(info.st_rdev);
    return kind >= 136 && kind <= 143;
}

protocol::Result<asio::serial_port, std::string> open_serial_port(asio::any_io_executor executor,
                                                                  const SerialSettings& settings) {
    using Port = asio::serial_port;
    Port port(std::move(executor));
    asio::error_code ec;
    port.open(settings.device, ec);
    if (ec) return open_error(settings, ec, "open");
    const auto stop = settings.stop_bits == 2 ? Port::stop_bits::two : Port::stop_bits::one;
    port.set_option(Port::baud_rate(settings.baud), ec);
    if (ec) return open_error(settings, ec, "set " + std::to_string(settings.baud) + " baud on");
    port.set_option(Port::character_size(settings.data_bits), ec);
    if (ec) {
        // Linux pseudo-terminals refuse 7-bit characters, the [SER] default for ASCII.
        return open_error(settings, ec,
                          "set " + std::to_string(settings.data_bits) + " data bits on") +
               (settings.data_bits != 8 ? " (try data=8; pseudo-terminals take only 8)" : "");
    }
    port.set_option(Port::parity(parity_option(settings.parity)), ec);
    if (!ec) port.set_option(Port::stop_bits(stop), ec);
    if (!ec) port.set_option(Port::flow_control(Port::flow_control::none), ec);
    if (ec) return open_error(settings, ec, "set parity, stop bits and flow control on");
    return port;
}

SerialFaultMonitor::SerialFaultMonitor(int fd) : fd_(fd) {
    supported_ = read_counts(last_);
}

bool SerialFaultMonitor::read_counts(Faults& counts) const {
    serial_icounter_struct icount{};
    if (::ioctl(fd_, TIOCGICOUNT, &icount) != 0) return false;
    counts.overruns =
        static_cast<std::uint32_t>(icount.overrun) + static_cast<std::uint32_t>(icount.buf_overrun);
    counts.parity_errors =
        static_cast<std::uint32_t>(icount.parity) + static_cast<std::uint32_t>(icount.frame);
    return true;
}

SerialFaultMonitor::Faults SerialFaultMonitor::poll() {
    Faults now{};
    if (!supported_ || !read_counts(now)) return {};
    // The driver's counters are ints that may wrap; unsigned subtraction takes that in stride.
    const Faults delta{now.overruns - last_.overruns, now.parity_errors - last_.parity_errors};
    last_ = now;
    return delta;
}

}  // namespace mblab::transport
