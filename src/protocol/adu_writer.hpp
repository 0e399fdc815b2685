#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

// Writers that wrap a PDU into a whole ADU in a caller buffer. They return the bytes written, or
// 0 when `out` is too small (nothing useful is written then). They do not enforce the PDU limit
// of 253 bytes: the tester must be able to put oversized frames on the wire.
namespace mblab::protocol {

// MBAP header + PDU. header.length is ignored and computed (1 + pdu.size()); 0 is returned when
// that does not fit 16 bits. `pdu` may already sit at out[7..] (it is moved, not copied), so a
// server can write the response PDU in place and add the header afterwards.
std::size_t write_mbap_adu(const MbapHeader& header, std::span<const std::uint8_t> pdu,
                           std::span<std::uint8_t> out);
// Sets the transaction id of the MBAP frame in `adu`: the load generator sends one frame many
// times under fresh ids.
inline void put_mbap_transaction_id(std::span<std::uint8_t> adu, std::uint16_t id) {
    adu[0] = static_cast<std::uint8_t>(id >> 8);
    adu[1] = static_cast<std::uint8_t>(id & 0xFF);
}
// Where write_mbap_adu() puts the PDU in `out`, for an answer written in place.
inline std::span<std::uint8_t> mbap_pdu_room(std::span<std::uint8_t> out) {
    return out.subspan(limits::kMbapHeader);
}

// Address + PDU + CRC-16 (low byte first). `pdu` may already sit at out[1..].
std::size_t write_rtu_adu(std::uint8_t address, std::span<const std::uint8_t> pdu,
                          std::span<std::uint8_t> out);

// ':' + uppercase hex of address, PDU and LRC + CR + `end` (LF unless changed by FC 08
// sub-function 03). Writes 2 * pdu.size() + 7 characters; `pdu` must not overlap `out`.
std::size_t write_ascii_adu(std::uint8_t address, std::span<const std::uint8_t> pdu,
                            std::span<std::uint8_t> out, std::uint8_t end = '\n');

}  // namespace mblab::protocol
