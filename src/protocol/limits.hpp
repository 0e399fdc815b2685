#pragma once

#include <cstddef>
#include <cstdint>

// Limits of [APP] and [TCPG] (docs/references.md).
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
inline constexpr std::size_t kFileRecordSubRequestSize = 7;  // reference type, file, record, length
// FC 14 request byte count, and the largest FC 14 response data length ([APP] 6.14).
inline constexpr std::uint8_t kMinFileRecordByteCount = 0x07;
inline constexpr std::uint8_t kMaxFileRecordByteCount = 0xF5;
// FC 15 request data length: [APP] 6.15's field table gives 0x09..0xFB (one sub-request with one
// register up to a full PDU); its state diagram repeats FC 14's 0x07..0xF5, which would refuse
// writes that fit the PDU. We follow the field table.
inline constexpr std::uint8_t kMinWriteFileRecordByteCount = 0x09;
inline constexpr std::uint8_t kMaxWriteFileRecordByteCount = 0xFB;

// FC 2B / 0E read device id codes and conformity levels ([APP] 6.21).
inline constexpr std::uint8_t kMinReadDeviceIdCode = 0x01;
inline constexpr std::uint8_t kMaxReadDeviceIdCode = 0x04;
inline constexpr std::uint8_t kReadDeviceIdIndividual = 0x04;
// FC 5B: protocol, class, instance and service code follow the fragment byte count (CTP
// 7.13.1.4); a response adds the service error code (7.13.1.5).
inline constexpr std::size_t kMinObjectMessagingRequestFragment = 7;
inline constexpr std::size_t kMinObjectMessagingResponseFragment = 9;

}  // namespace mblab::protocol::limits
