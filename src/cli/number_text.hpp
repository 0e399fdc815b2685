#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

// Numbers as users type them on the command line: decimal, or hex with 0x.
namespace mblab::cli {

std::optional<std::uint64_t> parse_unsigned(std::string_view text, std::uint64_t max);
std::optional<std::int64_t> parse_signed(std::string_view text, std::int64_t min, std::int64_t max);
std::optional<double> parse_real(std::string_view text);

// "0 (0x0000)": how every command shows an address.
std::string address_text(unsigned address);

}  // namespace mblab::cli
