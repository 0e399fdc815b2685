#pragma once

#include <cstdint>
#include <span>

namespace mblab::protocol {

// CRC-16 of Modbus RTU [SER 6.2.2]: polynomial 0xA001 (reflected 0x8005), initial value 0xFFFF,
// no final xor. On the wire the low byte goes first, so running crc16() over a whole frame
// including its two CRC bytes gives 0.
std::uint16_t crc16(std::span<const std::uint8_t> bytes);

// One step of the same CRC, for callers that see bytes one at a time.
std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte);

inline constexpr std::uint16_t kCrc16Initial = 0xFFFF;

}  // namespace mblab::protocol
