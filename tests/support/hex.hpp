#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// Test vectors are written the way conformance labs write them: "00 00 00 00 00 06 01 03 ...".
namespace mblab::test {

// Parses hex bytes separated by optional spaces; aborts the test binary on malformed input.
std::vector<std::uint8_t> hex(std::string_view text);
// "01 03 00 00" (uppercase, space separated).
std::string to_hex(std::span<const std::uint8_t> bytes);

}  // namespace mblab::test
