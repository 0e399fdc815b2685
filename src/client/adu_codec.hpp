#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/link.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/result.hpp"

// Wraps request PDUs for a link's framing and splits the frames it receives. Used both by the
// transactions and by the frame log, so what --decode shows is exactly what the client judged.
namespace mblab::client {

struct AduParts {
    std::optional<protocol::MbapHeader> mbap;  // Framing::Mbap only
    std::uint8_t unit = 0;                     // unit id or serial address
    std::vector<std::uint8_t> pdu;             // ASCII frames carry it as hex: decoded here
};

// Writes the whole ADU into `out`; 0 when it does not fit.
std::size_t wrap_pdu(Framing framing, std::uint8_t unit, std::uint16_t transaction_id,
                     std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out);

// Splits a frame of `framing`; the error says what makes it no frame (a protocol id other than
// 0, a length field that disagrees with the bytes, a bad CRC). An empty PDU is not an error here.
protocol::Result<AduParts, std::string> unwrap_frame(Framing framing,
                                                     std::span<const std::uint8_t> frame);

// "0x002A": the way every client message shows a 16-bit field.
std::string hex16(unsigned value);
std::string hex8(unsigned value);

}  // namespace mblab::client
