#include "robustness/line_cases.hpp"

#include <fmt/core.h>

#include <array>
#include <string>

#include "protocol/crc16.hpp"
#include "protocol/framer.hpp"
#include "protocol/lrc.hpp"
#include "robustness/liveness.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;
using protocol::Framing;

Bytes text_bytes(std::string_view text) {
    return {text.begin(), text.end()};
}

// ':' + hex of `bytes` as given (no LRC added) + `end`: ASCII frames whose check is chosen.
Bytes ascii_text(std::span<const std::uint8_t> bytes, std::string_view end = "\r\n") {
    std::string out = ":";
    for (auto byte : bytes)
        out += fmt::format("{:02X}", byte);
    out += end;
    return text_bytes(out);
}

// Address + PDU + a CRC the caller chose.
Bytes rtu_with_crc(std::span<const std::uint8_t> body, std::uint16_t crc) {
    Bytes out(body.begin(), body.end());
    out.push_back(static_cast<std::uint8_t>(crc));
    out.push_back(static_cast<std::uint8_t>(crc >> 8));
    return out;
}

FuzzCase one_step(BadInput kind, std::string name, Bytes bytes) {
    FuzzCase c{kind, std::move(name), {}, false};
    c.steps.push_back({0, std::move(bytes), {}});
    return c;
}

// `bad` on its own, the line left quiet, then the good read: a device that recovers answers it.
FuzzCase then_good(BadInput kind, std::string name, Bytes bad, std::chrono::milliseconds quiet,
                   Bytes good) {
    FuzzCase c{kind, std::move(name), {}, false};
    c.steps.push_back({0, std::move(bad), quiet});
    c.steps.push_back({0, std::move(good), {}});
    return c;
}

void rtu_only(std::vector<FuzzCase>& out, const Bytes& body, const Bytes& good,
              std::chrono::milliseconds gap) {
    const auto crc = protocol::crc16(body);
    out.push_back(
        one_step(BadInput::FrameCheck, "CRC low byte flipped", rtu_with_crc(body, crc ^ 0x00FF)));
    out.push_back(
        one_step(BadInput::FrameCheck, "CRC bytes swapped",
                 rtu_with_crc(body, static_cast<std::uint16_t>((crc << 8) | (crc >> 8)))));
    out.push_back(one_step(BadInput::FrameCheck, "CRC 0000", rtu_with_crc(body, 0)));
    Bytes broadcast = body;
    broadcast[0] = 0;
    out.push_back(one_step(BadInput::FrameCheck, "bad CRC to address 0 (broadcast)",
                           rtu_with_crc(broadcast, protocol::crc16(broadcast) ^ 0x0101)));
    // Another device's frame, corrupted: a receiver must drop it whatever its address says.
    Bytes last = body;
    last[0] = 247;
    out.push_back(one_step(BadInput::FrameCheck, "bad CRC to address 247 (the last unicast)",
                           rtu_with_crc(last, protocol::crc16(last) ^ 0x0101)));
    for (std::size_t size = 1; size <= 3; ++size) {
        out.push_back(one_step(BadInput::ShortFrame, fmt::format("{}-byte frame", size),
                               Bytes(good.begin(), good.begin() + static_cast<long>(size))));
    }
    const Bytes address = {body[0]};
    out.push_back(one_step(BadInput::ShortFrame, "address and CRC alone (3 bytes)",
                           rtu_with_crc(address, protocol::crc16(address))));
    for (std::size_t cut : {std::size_t{1}, good.size() / 2}) {
        FuzzCase c{BadInput::LineGap,
                   fmt::format("good read with a {} ms gap after byte {}", gap.count(), cut),
                   {},
                   false};
        c.steps.push_back({0, Bytes(good.begin(), good.begin() + static_cast<long>(cut)), gap});
        c.steps.push_back({0, Bytes(good.begin() + static_cast<long>(cut), good.end()), {}});
        out.push_back(std::move(c));
    }
}

void ascii_only(std::vector<FuzzCase>& out, const Bytes& body, const Bytes& good,
                std::chrono::milliseconds quiet) {
    Bytes checked = body;
    checked.push_back(static_cast<std::uint8_t>(protocol::lrc(body) + 1));
    out.push_back(one_step(BadInput::FrameCheck, "LRC off by one", ascii_text(checked)));
    checked.back() = 0;
    out.push_back(one_step(BadInput::FrameCheck, "LRC 00", ascii_text(checked)));
    out.push_back(one_step(BadInput::ShortFrame, "':' CR LF", text_bytes(":\r\n")));
    const Bytes address = {body[0], static_cast<std::uint8_t>(protocol::lrc(Bytes{body[0]}))};
    out.push_back(one_step(BadInput::ShortFrame, "address and LRC alone", ascii_text(address)));
    std::string text(good.begin(), good.end());
    out.push_back(then_good(BadInput::AsciiText, "odd number of hex digits",
                            text_bytes(text.substr(0, 3) + text.substr(4)), quiet, good));
    std::string not_hex = text;
    not_hex[3] = 'G';
    out.push_back(then_good(BadInput::AsciiText, "a character that is not hex", text_bytes(not_hex),
                            quiet, good));
    out.push_back(then_good(BadInput::AsciiText, "no CR LF, then a good frame",
                            text_bytes(text.substr(0, text.size() - 2)), quiet, good));
    out.push_back(then_good(BadInput::AsciiText, "CR without LF",
                            text_bytes(text.substr(0, text.size() - 1)), quiet, good));
}

}  // namespace

std::vector<std::uint8_t> line_frame(Framing framing, std::uint8_t address,
                                     std::span<const std::uint8_t> pdu) {
    Bytes out(protocol::adu_size(framing, pdu.size()));
    out.resize(protocol::write_adu({framing, address}, pdu, out));
    return out;
}

std::optional<std::string_view> not_applicable(BadInput kind, Framing framing) {
    struct Row {
        BadInput kind;
        std::string_view why;
    };
    constexpr std::string_view kNoMbapHeader = "an MBAP header field: a serial line has none";
    constexpr std::string_view kOneAtATime = "a serial line carries one request at a time";
    // The classes of Modbus/TCP alone, and why each is out of place on a serial line.
    static constexpr std::array<Row, 9> kTcpOnly{{
        {BadInput::ProtocolId, kNoMbapHeader},
        {BadInput::MbapLength, kNoMbapHeader},
        {BadInput::PartialHeader, kNoMbapHeader},
        {BadInput::SplitFrame, "TCP segments: on a line a pause inside a frame is line-gap"},
        {BadInput::Pipelined, kOneAtATime},
        {BadInput::ManyConnections, "a serial line is one connection"},
        {BadInput::SlowReader, "a serial line has no send buffer to fill"},
        {BadInput::HalfOpen, "a serial line has no connection to leave half-open"},
        {BadInput::Flood, kOneAtATime},
    }};
    if (framing != Framing::Mbap) {
        for (const Row& row : kTcpOnly) {
            if (row.kind == kind) return row.why;
        }
    } else if (kind == BadInput::FrameCheck || kind == BadInput::ShortFrame ||
               kind == BadInput::Noise) {
        return "a serial-line class: the target speaks Modbus/TCP";
    }
    if (kind == BadInput::LineGap && framing != Framing::Rtu)
        return "RTU timing: the target does not speak RTU";
    if (kind == BadInput::AsciiText && framing != Framing::Ascii)
        return "ASCII text: the target does not speak ASCII";
    return std::nullopt;
}

std::optional<FuzzCase> on_line(const FuzzCase& c, Framing framing) {
    if (not_applicable(c.kind, framing)) return std::nullopt;
    FuzzCase out{c.kind, c.name, {}, false};
    protocol::Framer mbap({Framing::Mbap});
    for (const auto& step : c.steps) {
        // Only whole, plain Modbus/TCP requests carry over: the rest test the MBAP header.
        const auto request = mbap.whole_frame(step.bytes);
        if (step.connection != 0 || !request || request->pdu.empty()) return std::nullopt;
        out.steps.push_back(
            {0, line_frame(framing, request->header.unit, request->pdu), step.pause});
    }
    return out;
}

std::vector<FuzzCase> line_cases(Framing framing, std::uint8_t address, std::uint16_t reg,
                                 std::chrono::milliseconds gap) {
    const auto read = conformance::known_good_read(reg);
    // Spelled out rather than inserted: g++ 12 takes the insert for an out-of-bounds copy.
    const Bytes body = {address, read[0], read[1], read[2], read[3], read[4]};
    const auto good = line_frame(framing, address, read);
    // Long enough for any line to fall quiet: noise must end as a frame of its own.
    const auto quiet = gap * 4;
    std::vector<FuzzCase> out;
    if (framing == Framing::Ascii) {
        ascii_only(out, body, good, quiet);
        out.push_back(then_good(BadInput::Noise, "text that is not a frame, then a good frame",
                                text_bytes("garbage\r\n"), quiet, good));
    } else {
        rtu_only(out, body, good, gap);
    }
    out.push_back(
        then_good(BadInput::Noise, "4 zero bytes, then a good frame", Bytes(4, 0x00), quiet, good));
    out.push_back(
        then_good(BadInput::Noise, "8 bytes 0xFF, then a good frame", Bytes(8, 0xFF), quiet, good));
    Bytes pattern;
    for (int i = 0; i < 32; ++i)
        pattern.push_back(static_cast<std::uint8_t>(i * 37 + 11));
    out.push_back(
        then_good(BadInput::Noise, "32 stray bytes, then a good frame", pattern, quiet, good));
    return out;
}

}  // namespace mblab::robustness
