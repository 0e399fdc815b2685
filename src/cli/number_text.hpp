#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

// Numbers as users type them on the command line: decimal, or hex with 0x.
namespace mblab::cli {

std::optional<std::uint64_t> parse_unsigned(std::string_view text, std::uint64_t max);
std::optional<std::int64_t> parse_signed(std::string_view text, std::int64_t min, std::int64_t max);
std::optional<double> parse_real(std::string_view text);

// A duration as typed: a number with a unit, 250ms, 1s, 1.5s, 2m, 1h, a sum of them, 1h30m, or a
// bare number alone, which is in `bare_unit` (the unit the option always took, so command lines
// written before units keep their meaning). nullopt for anything else: 1x, -1s, 1e3, inf, 1m30,
// an empty text.
std::optional<std::chrono::duration<double>> parse_duration(
    std::string_view text, std::chrono::duration<double> bare_unit);

// "0 (0x0000)": how every command shows an address.
std::string address_text(unsigned address);

}  // namespace mblab::cli
