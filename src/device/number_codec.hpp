#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "device/behaviour_spec.hpp"

// A number as the registers (or the bit) that hold it, in the layout's type, byte and word order
// and scaling, and back. Integers are rounded to the nearest and saturate at their type's bounds,
// so a value out of range reads as the nearest one the registers can hold.
namespace mblab::device {

struct NumberWords {
    std::array<std::uint16_t, 4> words{};
    std::uint32_t count = 1;

    std::span<const std::uint16_t> view() const { return {words.data(), count}; }
};

// A register type by its profile name (u16, i16, u32, i32, u64, i64, f32, f64); the names
// listed for messages.
std::optional<NumberType> register_type_named(std::string_view name);
std::string register_type_names();
// The profile's name of a register type ("f32"); "bit" for a bit.
std::string_view register_type_name(NumberType type);
// The order as the profile writes it: ABCD, CDAB, BADC or DCBA.
std::string order_letters(ByteOrder order);

// The largest value the registers of `type` hold, before scaling.
double largest_raw(NumberType type);

NumberWords encode_number(double value, const NumberLayout& layout);
// `words` holds number_width(layout.type) registers.
double decode_number(std::span<const std::uint16_t> words, const NumberLayout& layout);
// The raw value of `bits`, the type's width in the low bits, before scaling.
double number_from_bits(std::uint64_t bits, NumberType type);

}  // namespace mblab::device
