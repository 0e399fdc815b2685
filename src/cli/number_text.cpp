#include "cli/number_text.hpp"

#include <fmt/core.h>

#include <charconv>
#include <cstdlib>
#include <string>

namespace mblab::cli {

std::optional<std::uint64_t> parse_unsigned(std::string_view text, std::uint64_t max) {
    int base = 10;
    if (text.starts_with("0x") || text.starts_with("0X")) {
        text.remove_prefix(2);
        base = 16;
    }
    std::uint64_t value = 0;
    const char* end = text.data() + text.size();
    auto [stop, error] = std::from_chars(text.data(), end, value, base);
    if (text.empty() || error != std::errc{} || stop != end || value > max) return std::nullopt;
    return value;
}

std::optional<std::int64_t> parse_signed(std::string_view text, std::int64_t min,
                                         std::int64_t max) {
    const bool negative = text.starts_with('-');
    if (negative) text.remove_prefix(1);
    const auto limit = static_cast<std::uint64_t>(negative ? -(min + 1) : max) + (negative ? 1 : 0);
    auto magnitude = parse_unsigned(text, limit);
    if (!magnitude) return std::nullopt;
    if (!negative) return static_cast<std::int64_t>(*magnitude);
    return *magnitude == 0 ? 0 : -static_cast<std::int64_t>(*magnitude - 1) - 1;
}

std::optional<double> parse_real(std::string_view text) {
    // std::from_chars for double is missing from some of the standard libraries we build with.
    std::string copy(text);
    char* end = nullptr;
    const double value = std::strtod(copy.c_str(), &end);
    if (copy.empty() || end != copy.c_str() + copy.size()) {
        return std::nullopt;
    }
    return value;
}

std::string address_text(unsigned address) {
    return fmt::format("{} (0x{:04X})", address, address);
}

}  // namespace mblab::cli
