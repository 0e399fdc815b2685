#pragma once

#include <cstddef>
#include <cstdint>

// Limits of [APP] and [TCPG] as PROTOCOL.md lists them.
namespace mblab::protocol::limits {

inline constexpr std::size_t kMaxPdu = 253;
inline constexpr std::size_t kMaxTcpAdu = 260;
inline constexpr std::size_t kMbapHeader = 7;
inline constexpr std::size_t kMaxRtuAdu = 256;
inline constexpr std::size_t kMaxAsciiChars = 513;

inline constexpr std::uint16_t kMaxReadBits = 2000;
inline constexpr std::uint16_t kMaxReadRegisters = 125;
inline constexpr std::uint16_t kMaxWriteCoils = 1968;
inline constexpr std::uint16_t kMaxWriteRegisters = 123;
inline constexpr std::uint16_t kMaxReadWriteRead = 125;
inline constexpr std::uint16_t kMaxReadWriteWrite = 121;
inline constexpr std::uint16_t kMaxFifoCount = 31;
inline constexpr std::size_t kMaxEventLogEvents = 64;
inline constexpr std::uint8_t kFileRecordReferenceType = 6;
inline constexpr std::uint16_t kMaxFileRecordNumber = 9999;
inline constexpr std::uint8_t kMinFileRecordByteCount = 0x07;
inline constexpr std::uint8_t kMaxFileRecordByteCount = 0xF5;

}  // namespace mblab::protocol::limits
