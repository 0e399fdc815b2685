#include "client/adu_codec.hpp"

#include <cstdio>

#include "protocol/adu.hpp"
#include "protocol/ascii_framer.hpp"
#include "protocol/crc16.hpp"
#include "protocol/limits.hpp"

namespace mblab::client {

namespace {

constexpr std::size_t kRtuOverhead = 3;  // address + CRC

protocol::Result<AduParts, std::string> unwrap_mbap(std::span<const std::uint8_t> frame) {
    if (frame.size() < protocol::limits::kMbapHeader) {
        return "the frame is " + std::to_string(frame.size()) +
               " bytes long, shorter than an MBAP header (7)";
    }
    AduParts parts;
    parts.mbap = protocol::read_mbap_header(frame);
    const auto& header = *parts.mbap;
    if (header.protocol_id != 0) {
        return "MBAP protocol id is " + hex16(header.protocol_id) + ", expected 0x0000 (Modbus)";
    }
    if (header.length + 6U != frame.size()) {
        return "MBAP length " + std::to_string(header.length) + " disagrees with the " +
               std::to_string(frame.size() - 6) + " bytes after it";
    }
    parts.unit = header.unit_id;
    const auto pdu = frame.subspan(protocol::limits::kMbapHeader);
    parts.pdu.assign(pdu.begin(), pdu.end());
    return parts;
}

protocol::Result<AduParts, std::string> unwrap_rtu(std::span<const std::uint8_t> frame) {
    if (frame.size() < kRtuOverhead) {
        return "the frame is " + std::to_string(frame.size()) + " bytes long, too short for RTU";
    }
    if (protocol::crc16(frame) != 0) return std::string("the RTU frame's CRC does not match");
    AduParts parts;
    parts.unit = frame[0];
    const auto pdu = frame.subspan(1, frame.size() - kRtuOverhead);
    parts.pdu.assign(pdu.begin(), pdu.end());
    return parts;
}

protocol::Result<AduParts, std::string> unwrap_ascii(std::span<const std::uint8_t> frame) {
    protocol::AsciiFramer framer;
    std::size_t consumed = 0;
    const auto event = framer.feed(frame, consumed);
    if (event.is_error()) return std::string("the ASCII frame is broken: ") + event.error;
    if (!event.is_frame() || consumed != frame.size()) {
        return std::string("the bytes are not one whole ASCII frame");
    }
    AduParts parts;
    parts.unit = event.header.unit;
    parts.pdu.assign(event.pdu.begin(), event.pdu.end());
    return parts;
}

}  // namespace

std::string hex16(unsigned value) {
    char text[8];
    std::snprintf(text, sizeof text, "0x%04X", value & 0xFFFFU);
    return text;
}

std::string hex8(unsigned value) {
    char text[8];
    std::snprintf(text, sizeof text, "0x%02X", value & 0xFFU);
    return text;
}

std::size_t wrap_pdu(Framing framing, std::uint8_t unit, std::uint16_t transaction_id,
                     std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out) {
    return protocol::write_adu({framing, unit, transaction_id}, pdu, out);
}

protocol::Result<AduParts, std::string> unwrap_frame(Framing framing,
                                                     std::span<const std::uint8_t> frame) {
    switch (framing) {
        case Framing::Mbap:
            return unwrap_mbap(frame);
        case Framing::Rtu:
            return unwrap_rtu(frame);
        case Framing::Ascii:
            return unwrap_ascii(frame);
    }
    return std::string("unknown framing");
}

}  // namespace mblab::client
