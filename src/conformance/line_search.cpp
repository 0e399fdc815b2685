#include "conformance/line_search.hpp"

#include <array>

#include "client/stream_link.hpp"
#include "conformance/serial_line_probe.hpp"
#include "protocol/adu.hpp"
#include "protocol/limits.hpp"

namespace mblab::conformance {

namespace {

// Whether the device answers one FC 03 read (with data or an exception) at `url`'s settings.
bool answers_at(const transport::SerialUrl& url, std::uint8_t unit,
                std::chrono::milliseconds timeout) {
    auto opened = client::StreamLink::open_serial(url, transport::format_serial_url(url));
    if (!opened) return false;
    const auto framing = url.kind == transport::SerialUrl::Kind::Ascii ? protocol::Framing::Ascii
                                                                       : protocol::Framing::Rtu;
    const auto pdu = read_holding(0);
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> wire{};
    const auto size = protocol::write_adu({.framing = framing, .unit = unit}, pdu, wire);
    client::LinkError error;
    if (!opened.value()->send(std::span(wire).first(size), error)) return false;
    const auto received = opened.value()->receive_frame(timeout);
    return received.status == client::ReceiveStatus::Frame && received.header.unit == unit;
}

}  // namespace

std::string line_search_hint(const client::Target& target, const Dut& dut,
                             std::chrono::milliseconds timeout) {
    if (!target.serial || target.serial->kind == transport::SerialUrl::Kind::RtuOverTcp) return {};
    for (const auto& setting : dut.line_settings) {
        const auto url = transport::with_line_settings(*target.serial, setting);
        // RTU characters carry 8 data bits [SER 2.5.1]: a 7-bit setting is ASCII's alone.
        if (url.kind == transport::SerialUrl::Kind::Rtu && url.line.data_bits != 8) continue;
        if (!answers_at(url, dut.unit, timeout)) continue;
        return "; it answers at " + setting + " (declared in line_settings): run with " +
               transport::format_serial_url(url);
    }
    return {};
}

}  // namespace mblab::conformance
