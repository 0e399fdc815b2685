#include "cli/modbus_address.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <string_view>

#include "cli/number_text.hpp"
#include "support/name_table.hpp"

namespace mblab::cli {

namespace {

bool all_digits(std::string_view text) {
    return !text.empty() &&
           std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::optional<DataTable> table_of(char digit) {
    switch (digit) {
        case '0':
            return DataTable::Coils;
        case '1':
            return DataTable::Discretes;
        case '3':
            return DataTable::Input;
        case '4':
            return DataTable::Holding;
        default:
            return std::nullopt;
    }
}

struct Reference {
    DataTable table;
    std::uint32_t number;  // 1-based
};

// 4x0001, 4x00001, 400001. 0x... is not here: it is hex (see the header).
std::optional<Reference> parse_reference(std::string_view text) {
    std::string_view digits;
    char lead = 0;
    if (text.size() >= 6 && text.size() <= 7 && (text[1] == 'x' || text[1] == 'X') &&
        text[0] != '0') {
        lead = text[0];
        digits = text.substr(2);
    } else if (text.size() == 6) {
        lead = text[0];
        digits = text.substr(1);
    } else {
        return std::nullopt;
    }
    auto table = table_of(lead);
    if (!table || !all_digits(digits)) return std::nullopt;
    auto number = parse_unsigned(digits, 99999);
    if (!number) return std::nullopt;
    return Reference{*table, static_cast<std::uint32_t>(*number)};
}

}  // namespace

const char* table_name(DataTable table) {
    static constexpr Named<DataTable, const char*> kNames[] = {
        {DataTable::Coils, "coils"},
        {DataTable::Discretes, "discrete inputs"},
        {DataTable::Input, "input registers"},
        {DataTable::Holding, "holding registers"}};
    return name_of(kNames, table, "?");
}

protocol::Result<std::uint16_t, std::string> parse_address(const std::string& text,
                                                           const char* name, DataTable table,
                                                           int base) {
    if (auto reference = parse_reference(text)) {
        const auto digit = static_cast<unsigned>(table);
        if (reference->table != table) {
            return fmt::format("{} {} is a reference to {} ({}x), not to {} ({}x)", name, text,
                               table_name(reference->table),
                               static_cast<unsigned>(reference->table), table_name(table), digit);
        }
        if (reference->number < 1 || reference->number > 0x10000) {
            return fmt::format("{} {}: a {}x reference is from {}x00001 to {}x65536", name, text,
                               digit, digit, digit);
        }
        return static_cast<std::uint16_t>(reference->number - 1);
    }
    const std::uint64_t max = base == 1 ? 0x10000 : 0xFFFF;
    auto value = parse_unsigned(text, max);
    if (!value) {
        return fmt::format("{} must be a number from {} to {}{} (decimal or 0x hex), got '{}'",
                           name, base, max, base == 1 ? " with --base 1" : "", text);
    }
    if (base == 1) {
        if (*value == 0) {
            return fmt::format("{} 0 with --base 1: 1-based addresses start at 1", name);
        }
        return static_cast<std::uint16_t>(*value - 1);
    }
    return static_cast<std::uint16_t>(*value);
}

std::optional<std::string> reference_hint(const std::string& text, DataTable table, int base) {
    if (base != 0 || text.size() != 5 || !all_digits(text)) return std::nullopt;
    if (table_of(text[0]) != table) return std::nullopt;
    const auto number = parse_unsigned(text.substr(1), 9999).value_or(0);
    if (number == 0) return std::nullopt;
    return fmt::format("{} looks like a Modicon reference: try {}x{:05} or --base 1 with {}", text,
                       text[0], number, number);
}

}  // namespace mblab::cli
