#pragma once

#include <cstdint>
#include <span>

namespace mblab::protocol {

// LRC of Modbus ASCII [SER 6.2.2]: the two's complement of the 8-bit sum of the bytes (address
// and PDU). Summing a frame's bytes together with its LRC gives 0.
std::uint8_t lrc(std::span<const std::uint8_t> bytes);

}  // namespace mblab::protocol
