#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/result.hpp"

// Typed register values (--type, --word-order, --byte-order): how `read` shows registers and how
// `write` makes them, the same rules both ways. A value of 32 or 64 bits spans 2 or 4 registers;
// word order says which register holds the most significant word, byte order which byte of each
// register comes first. Big / big is the Modbus convention and the profile's (high word first).
namespace mblab::cli {

enum class ValueType : std::uint8_t { U16, I16, U32, I32, F32, F64, Hex, Ascii };
enum class Order : std::uint8_t { Big, Little };

struct ValueFormat {
    ValueType type = ValueType::U16;
    Order word_order = Order::Big;
    Order byte_order = Order::Big;
};

inline constexpr std::string_view kValueTypeNames = "u16, i16, u32, i32, f32, f64, hex, ascii";

std::optional<ValueType> parse_value_type(std::string_view name);
std::optional<Order> parse_order(std::string_view name);
std::string_view value_type_name(ValueType type);
// Registers one value takes: 1, 2 or 4 (ascii: 1 register, two characters).
std::size_t registers_per_value(ValueType type);

// One value from exactly registers_per_value() registers.
std::string format_value(std::span<const std::uint16_t> registers, const ValueFormat& format);
// The same value for --json: a number, or a string for hex and ascii.
nlohmann::json json_value(std::span<const std::uint16_t> registers, const ValueFormat& format);
// "0x4048 0xF5C3"
std::string raw_text(std::span<const std::uint16_t> registers);

// The registers of one value as typed ("42", "-1", "3.5", "0x2A", "text"). An ascii value takes
// as many registers as its characters need (two per register, padded with 0).
protocol::Result<std::vector<std::uint16_t>, std::string> encode_value(std::string_view text,
                                                                       const ValueFormat& format);
// Every value in order, or the first that is wrong.
protocol::Result<std::vector<std::uint16_t>, std::string> encode_values(
    const std::vector<std::string>& texts, const ValueFormat& format);

// The text of ascii registers, without trailing NULs.
std::string ascii_text(std::span<const std::uint16_t> registers, const ValueFormat& format);

}  // namespace mblab::cli
