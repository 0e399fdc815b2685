#pragma once

#include <cstdint>
#include <span>
#include <string>

// How every message, report and reproducer shows bytes and a field's value in hex, so that a
// transaction id, a function code or a frame reads the same in all of them.
namespace mblab::client {

// "0x002A"
std::string hex16(unsigned value);
// "0x2A"
std::string hex8(unsigned value);
// "0A FF 00": uppercase, one space between bytes, as conformance labs write frames.
std::string hex_bytes(std::span<const std::uint8_t> bytes);

}  // namespace mblab::client
