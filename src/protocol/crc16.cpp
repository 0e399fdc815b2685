#include "protocol/crc16.hpp"

#include <array>

namespace mblab::protocol {

namespace {

// Byte-at-a-time table: the eight shift/xor steps of the reflected CRC, done once per byte value.
constexpr std::array<std::uint16_t, 256> make_table() {
    std::array<std::uint16_t, 256> table{};
    for (unsigned value = 0; value < 256; ++value) {
        unsigned crc = value;
        for (int bit = 0; bit < 8; ++bit)
            crc = (crc & 1U) ? (crc >> 1) ^ 0xA001U : crc >> 1;
        table[value] = static_cast<std::uint16_t>(crc);
    }
    return table;
}

constexpr std::array<std::uint16_t, 256> kTable = make_table();

}  // namespace

std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte) {
    return static_cast<std::uint16_t>((crc >> 8) ^ kTable[(crc ^ byte) & 0xFFU]);
}

std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
    std::uint16_t crc = kCrc16Initial;
    for (std::uint8_t byte : bytes)
        crc = crc16_update(crc, byte);
    return crc;
}

}  // namespace mblab::protocol
