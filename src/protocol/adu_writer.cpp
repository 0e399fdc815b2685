#include "protocol/adu_writer.hpp"

#include <cstring>

#include "protocol/crc16.hpp"
#include "protocol/limits.hpp"
#include "protocol/lrc.hpp"
#include "support/hex_digits.hpp"

namespace mblab::protocol {

namespace {

void put_be16(std::uint8_t* out, std::uint16_t value) {
    out[0] = static_cast<std::uint8_t>(value >> 8);
    out[1] = static_cast<std::uint8_t>(value & 0xFF);
}

// Moves the PDU behind a prefix of `at` bytes; memmove because it may already be there.
void place_pdu(std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out, std::size_t at) {
    if (!pdu.empty()) std::memmove(out.data() + at, pdu.data(), pdu.size());
}

std::uint8_t* put_hex(std::uint8_t* out, std::uint8_t value) {
    *out++ = static_cast<std::uint8_t>(kHexDigits[value >> 4]);
    *out++ = static_cast<std::uint8_t>(kHexDigits[value & 0xF]);
    return out;
}

}  // namespace

std::size_t write_mbap_adu(const MbapHeader& header, std::span<const std::uint8_t> pdu,
                           std::span<std::uint8_t> out) {
    const std::size_t length = 1 + pdu.size();  // unit id + PDU
    const std::size_t size = limits::kMbapHeader + pdu.size();
    if (length > 0xFFFF || out.size() < size) return 0;
    place_pdu(pdu, out, limits::kMbapHeader);
    put_be16(&out[0], header.transaction_id);
    put_be16(&out[2], header.protocol_id);
    put_be16(&out[4], static_cast<std::uint16_t>(length));
    out[6] = header.unit_id;
    return size;
}

std::size_t write_rtu_adu(std::uint8_t address, std::span<const std::uint8_t> pdu,
                          std::span<std::uint8_t> out) {
    const std::size_t body = 1 + pdu.size();
    const std::size_t size = body + 2;
    if (out.size() < size) return 0;
    place_pdu(pdu, out, 1);
    out[0] = address;
    const std::uint16_t crc = crc16(out.first(body));
    out[body] = static_cast<std::uint8_t>(crc & 0xFF);
    out[body + 1] = static_cast<std::uint8_t>(crc >> 8);
    return size;
}

std::size_t write_ascii_adu(std::uint8_t address, std::span<const std::uint8_t> pdu,
                            std::span<std::uint8_t> out, std::uint8_t end) {
    // ':' + two digits for each of address, PDU bytes and LRC + CR + end.
    const std::size_t size = 1 + 2 * (pdu.size() + 2) + 2;
    if (out.size() < size) return 0;
    std::uint8_t* at = out.data();
    *at++ = ':';
    at = put_hex(at, address);
    for (std::uint8_t byte : pdu)
        at = put_hex(at, byte);
    // lrc() negates a sum, so taking the address out of it adds the address to the sum.
    at = put_hex(at, static_cast<std::uint8_t>(lrc(pdu) - address));
    *at++ = '\r';
    *at = end;
    return size;
}

}  // namespace mblab::protocol
