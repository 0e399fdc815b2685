#include "cli/value_format.hpp"

#include <fmt/core.h>

#include <array>
#include <bit>
#include <cstring>

#include "cli/number_text.hpp"
#include "support/escaped_text.hpp"

namespace mblab::cli {

namespace {

struct TypeInfo {
    ValueType type;
    std::string_view name;
    std::size_t registers;
};

constexpr std::array<TypeInfo, 8> kTypes = {{
    {ValueType::U16, "u16", 1},
    {ValueType::I16, "i16", 1},
    {ValueType::U32, "u32", 2},
    {ValueType::I32, "i32", 2},
    {ValueType::F32, "f32", 2},
    {ValueType::F64, "f64", 4},
    {ValueType::Hex, "hex", 1},
    {ValueType::Ascii, "ascii", 1},
}};

const TypeInfo& info(ValueType type) {
    return kTypes[static_cast<std::size_t>(type)];
}

std::uint16_t swap_bytes(std::uint16_t word) {
    return static_cast<std::uint16_t>((word << 8) | (word >> 8));
}

// The registers of one value, most significant word first, each with its high byte first.
std::uint64_t assemble(std::span<const std::uint16_t> registers, const ValueFormat& format) {
    std::uint64_t bits = 0;
    const std::size_t count = registers.size();
    for (std::size_t i = 0; i < count; ++i) {
        std::uint16_t word = registers[format.word_order == Order::Big ? i : count - 1 - i];
        if (format.byte_order == Order::Little) word = swap_bytes(word);
        bits = (bits << 16) | word;
    }
    return bits;
}

std::vector<std::uint16_t> split(std::uint64_t bits, std::size_t count, const ValueFormat& format) {
    std::vector<std::uint16_t> registers(count);
    for (std::size_t i = 0; i < count; ++i) {
        auto word = static_cast<std::uint16_t>(bits >> (16 * (count - 1 - i)));
        if (format.byte_order == Order::Little) word = swap_bytes(word);
        registers[format.word_order == Order::Big ? i : count - 1 - i] = word;
    }
    return registers;
}

// The two characters of a register in the order the byte order puts them.
std::array<std::uint8_t, 2> characters(std::uint16_t word, const ValueFormat& format) {
    if (format.byte_order == Order::Little) word = swap_bytes(word);
    return {static_cast<std::uint8_t>(word >> 8), static_cast<std::uint8_t>(word & 0xFF)};
}

std::string bad_value(std::string_view text, ValueType type, std::string_view range) {
    return fmt::format("'{}' is not a {} value ({})", text, info(type).name, range);
}

}  // namespace

std::optional<ValueType> parse_value_type(std::string_view name) {
    for (const auto& type : kTypes) {
        if (type.name == name) return type.type;
    }
    return std::nullopt;
}

std::optional<Order> parse_order(std::string_view name) {
    if (name == "big") return Order::Big;
    if (name == "little") return Order::Little;
    return std::nullopt;
}

std::string_view value_type_name(ValueType type) {
    return info(type).name;
}

std::size_t registers_per_value(ValueType type) {
    return info(type).registers;
}

std::string raw_text(std::span<const std::uint16_t> registers) {
    std::string text;
    for (auto word : registers)
        text += fmt::format("{}0x{:04X}", text.empty() ? "" : " ", word);
    return text;
}

std::string format_value(std::span<const std::uint16_t> registers, const ValueFormat& format) {
    const std::uint64_t bits = assemble(registers, format);
    switch (format.type) {
        case ValueType::U16:
        case ValueType::U32:
            return fmt::format("{}", bits);
        case ValueType::I16:
            return fmt::format("{}", static_cast<std::int16_t>(bits));
        case ValueType::I32:
            return fmt::format("{}", static_cast<std::int32_t>(bits));
        case ValueType::F32:
            return fmt::format("{}", std::bit_cast<float>(static_cast<std::uint32_t>(bits)));
        case ValueType::F64:
            return fmt::format("{}", std::bit_cast<double>(bits));
        case ValueType::Hex:
            return fmt::format("0x{:04X}", bits);
        case ValueType::Ascii: {
            const auto chars = characters(registers[0], format);
            return "\"" + escaped_text(chars) + "\"";
        }
    }
    return {};
}

nlohmann::json json_value(std::span<const std::uint16_t> registers, const ValueFormat& format) {
    const std::uint64_t bits = assemble(registers, format);
    switch (format.type) {
        case ValueType::U16:
        case ValueType::U32:
            return bits;
        case ValueType::I16:
            return static_cast<std::int16_t>(bits);
        case ValueType::I32:
            return static_cast<std::int32_t>(bits);
        case ValueType::F32:
            return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
        case ValueType::F64:
            return std::bit_cast<double>(bits);
        case ValueType::Hex:
            return fmt::format("0x{:04X}", bits);
        case ValueType::Ascii: {
            auto chars = characters(registers[0], format);
            return std::string{static_cast<char>(chars[0]), static_cast<char>(chars[1])};
        }
    }
    return nullptr;
}

std::string ascii_text(std::span<const std::uint16_t> registers, const ValueFormat& format) {
    std::string text;
    for (auto word : registers) {
        for (auto c : characters(word, format))
            text += static_cast<char>(c);
    }
    while (!text.empty() && text.back() == '\0')
        text.pop_back();
    return text;
}

protocol::Result<std::vector<std::uint16_t>, std::string> encode_value(std::string_view text,
                                                                       const ValueFormat& format) {
    const std::size_t count = registers_per_value(format.type);
    switch (format.type) {
        case ValueType::U16:
        case ValueType::U32: {
            const std::uint64_t max = count == 1 ? 0xFFFF : 0xFFFFFFFF;
            auto value = parse_unsigned(text, max);
            if (!value) return bad_value(text, format.type, fmt::format("0..{}", max));
            return split(*value, count, format);
        }
        case ValueType::I16:
        case ValueType::I32: {
            const std::int64_t max = count == 1 ? 0x7FFF : 0x7FFFFFFF;
            auto value = parse_signed(text, -max - 1, max);
            if (!value) return bad_value(text, format.type, fmt::format("{}..{}", -max - 1, max));
            const std::uint64_t mask = count == 1 ? 0xFFFF : 0xFFFFFFFF;
            return split(static_cast<std::uint64_t>(*value) & mask, count, format);
        }
        case ValueType::F32:
        case ValueType::F64: {
            auto value = parse_real(text);
            if (!value) return bad_value(text, format.type, "a decimal number");
            if (format.type == ValueType::F64)
                return split(std::bit_cast<std::uint64_t>(*value), 4, format);
            return split(std::bit_cast<std::uint32_t>(static_cast<float>(*value)), 2, format);
        }
        case ValueType::Hex: {
            std::string_view digits = text;
            if (digits.starts_with("0x") || digits.starts_with("0X")) digits.remove_prefix(2);
            auto value = digits.size() <= 4 ? parse_unsigned("0x" + std::string(digits), 0xFFFF)
                                            : std::nullopt;
            if (!value) return bad_value(text, format.type, "1 to 4 hex digits");
            return split(*value, 1, format);
        }
        case ValueType::Ascii: {
            if (text.empty()) return bad_value(text, format.type, "at least one character");
            std::vector<std::uint16_t> registers;
            for (std::size_t i = 0; i < text.size(); i += 2) {
                const auto high = static_cast<std::uint8_t>(text[i]);
                const auto low = static_cast<std::uint8_t>(i + 1 < text.size() ? text[i + 1] : 0);
                registers.push_back(split((high << 8) | low, 1, format)[0]);
            }
            return registers;
        }
    }
    return std::string("unknown type");
}

protocol::Result<std::vector<std::uint16_t>, std::string> encode_values(
    const std::vector<std::string>& texts, const ValueFormat& format) {
    std::vector<std::uint16_t> registers;
    for (const auto& text : texts) {
        auto value = encode_value(text, format);
        if (!value) return value.error();
        registers.insert(registers.end(), value->begin(), value->end());
    }
    return registers;
}

}  // namespace mblab::cli
