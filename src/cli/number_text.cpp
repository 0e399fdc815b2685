#include "cli/number_text.hpp"

#include <fmt/core.h>

#include <algorithm>
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

std::optional<std::chrono::duration<double>> parse_duration(
    std::string_view text, std::chrono::duration<double> bare_unit) {
    using std::chrono::duration;
    struct Unit {
        std::string_view suffix;
        duration<double> length;
    };
    // "ms" and "us" before "m" and "s", so 250ms is not read as 250m followed by junk.
    static constexpr Unit kUnits[] = {{"us", duration<double, std::micro>(1)},
                                      {"ms", duration<double, std::milli>(1)},
                                      {"s", duration<double>(1)},
                                      {"m", duration<double, std::ratio<60>>(1)},
                                      {"h", duration<double, std::ratio<3600>>(1)}};
    if (text.empty()) return std::nullopt;
    duration<double> total{0};
    // A sum of parts, 1h30m or 1m30.5s; a number without a unit only stands alone.
    for (bool alone = true; !text.empty(); alone = false) {
        // Digits and at most one point only: strtod would also take signs, exponents, hex and inf.
        const auto number = text.substr(0, text.find_first_not_of("0123456789."));
        text.remove_prefix(number.size());
        if (number.empty() || number == "." || number.find('.') != number.rfind('.'))
            return std::nullopt;
        const auto unit = std::find_if(std::begin(kUnits), std::end(kUnits),
                                       [&](const Unit& u) { return text.starts_with(u.suffix); });
        if (unit == std::end(kUnits) && !(alone && text.empty())) return std::nullopt;
        if (unit != std::end(kUnits)) text.remove_prefix(unit->suffix.size());
        total += *parse_real(number) * (unit == std::end(kUnits) ? bare_unit : unit->length);
    }
    return total;
}

std::string address_text(unsigned address) {
    return fmt::format("{} (0x{:04X})", address, address);
}

}  // namespace mblab::cli
