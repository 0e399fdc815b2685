#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "protocol/adu.hpp"

namespace mblab::protocol {

// The 7-byte MBAP header of Modbus/TCP [TCPG 3.1.3]. `length` counts the bytes that follow it:
// the unit id and the PDU.
struct MbapHeader {
    std::uint16_t transaction_id = 0;
    std::uint16_t protocol_id = kModbusProtocolId;
    std::uint16_t length = 0;
    std::uint8_t unit_id = 0;

    friend bool operator==(const MbapHeader&, const MbapHeader&) = default;
};

// Parses the first 7 bytes of `bytes`; the caller has checked there are at least 7.
MbapHeader read_mbap_header(std::span<const std::uint8_t> bytes);

// The same fields as the framing-neutral header that framers report, and back (`header` is an
// MBAP one: its framing is not checked).
inline AduHeader to_adu_header(const MbapHeader& header) {
    return {Framing::Mbap, header.unit_id, header.transaction_id, header.protocol_id,
            header.length};
}
inline MbapHeader to_mbap_header(const AduHeader& header) {
    return {header.transaction_id, header.protocol_id, header.length, header.unit};
}

// A Modbus/TCP frame as its header fields (the length field as it reads) and its PDU, function
// code first, empty in a frame of a header alone: how the tester reads the requests and answers
// of its catalogue, which are written as MBAP frames, instead of by byte position. The length
// field is read, not checked: judging it is the tester's business. nullopt when `bytes` are too
// few for a header.
std::optional<Adu> read_mbap_frame(std::span<const std::uint8_t> bytes);

}  // namespace mblab::protocol
