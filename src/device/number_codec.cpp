#include "device/number_codec.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace mblab::device {

namespace {

template <class Int>
Int saturate(double raw) {
    if (std::isnan(raw)) return 0;
    const double rounded = std::nearbyint(raw);
    if (rounded <= static_cast<double>(std::numeric_limits<Int>::min())) {
        return std::numeric_limits<Int>::min();
    }
    // The maximum of a 64-bit type rounds up to 2^64 or 2^63 as a double, so compare with >=.
    if (rounded >= static_cast<double>(std::numeric_limits<Int>::max())) {
        return std::numeric_limits<Int>::max();
    }
    return static_cast<Int>(rounded);
}

// The value's bits, most significant first, in the low `width * 16` bits.
std::uint64_t raw_bits(double raw, NumberType type) {
    switch (type) {
        case NumberType::Bit:
            return saturate<std::int64_t>(raw) != 0 ? 1 : 0;
        case NumberType::U16:
            return saturate<std::uint16_t>(raw);
        case NumberType::I16:
            return static_cast<std::uint16_t>(saturate<std::int16_t>(raw));
        case NumberType::U32:
            return saturate<std::uint32_t>(raw);
        case NumberType::I32:
            return static_cast<std::uint32_t>(saturate<std::int32_t>(raw));
        case NumberType::U64:
            return saturate<std::uint64_t>(raw);
        case NumberType::I64:
            return static_cast<std::uint64_t>(saturate<std::int64_t>(raw));
        case NumberType::F32:
            return std::bit_cast<std::uint32_t>(static_cast<float>(raw));
        case NumberType::F64:
            return std::bit_cast<std::uint64_t>(raw);
    }
    return 0;
}

constexpr std::array<std::pair<std::string_view, NumberType>, 8> kRegisterTypes = {{
    {"u16", NumberType::U16},
    {"i16", NumberType::I16},
    {"u32", NumberType::U32},
    {"i32", NumberType::I32},
    {"u64", NumberType::U64},
    {"i64", NumberType::I64},
    {"f32", NumberType::F32},
    {"f64", NumberType::F64},
}};

std::uint16_t swap_bytes(std::uint16_t word) {
    return static_cast<std::uint16_t>(word << 8 | word >> 8);
}

// Position in the bank of the i-th word counting from the most significant.
std::uint32_t word_slot(std::uint32_t i, std::uint32_t count, ByteOrder order) {
    return order.low_word_first ? count - 1 - i : i;
}

}  // namespace

std::uint32_t number_width(NumberType type) {
    switch (type) {
        case NumberType::U32:
        case NumberType::I32:
        case NumberType::F32:
            return 2;
        case NumberType::U64:
        case NumberType::I64:
        case NumberType::F64:
            return 4;
        default:
            return 1;
    }
}

std::optional<NumberType> register_type_named(std::string_view name) {
    for (const auto& [known, type] : kRegisterTypes) {
        if (known == name) return type;
    }
    return std::nullopt;
}

std::string register_type_names() {
    std::string names;
    for (const auto& [known, type] : kRegisterTypes)
        names += (names.empty() ? "" : ", ") + std::string(known);
    return names;
}

std::string_view register_type_name(NumberType type) {
    for (const auto& [known, each] : kRegisterTypes) {
        if (each == type) return known;
    }
    return "bit";
}

std::string order_letters(ByteOrder order) {
    std::string letters = order.low_word_first ? "CDAB" : "ABCD";
    if (order.low_byte_first) {
        std::swap(letters[0], letters[1]);
        std::swap(letters[2], letters[3]);
    }
    return letters;
}

double largest_raw(NumberType type) {
    switch (type) {
        case NumberType::Bit:
            return 1;
        case NumberType::U16:
            return std::numeric_limits<std::uint16_t>::max();
        case NumberType::I16:
            return std::numeric_limits<std::int16_t>::max();
        case NumberType::U32:
            return std::numeric_limits<std::uint32_t>::max();
        case NumberType::I32:
            return std::numeric_limits<std::int32_t>::max();
        case NumberType::U64:
            return static_cast<double>(std::numeric_limits<std::uint64_t>::max());
        case NumberType::I64:
            return static_cast<double>(std::numeric_limits<std::int64_t>::max());
        case NumberType::F32:
            return std::numeric_limits<float>::max();
        case NumberType::F64:
            return std::numeric_limits<double>::max();
    }
    return 0;
}

NumberWords encode_number(double value, const NumberLayout& layout) {
    NumberWords out;
    out.count = number_width(layout.type);
    const std::uint64_t bits = raw_bits((value - layout.offset) / layout.scale, layout.type);
    for (std::uint32_t i = 0; i < out.count; ++i) {
        auto word = static_cast<std::uint16_t>(bits >> (16 * (out.count - 1 - i)));
        if (layout.order.low_byte_first && layout.type != NumberType::Bit) word = swap_bytes(word);
        out.words[word_slot(i, out.count, layout.order)] = word;
    }
    return out;
}

double decode_number(std::span<const std::uint16_t> words, const NumberLayout& layout) {
    const std::uint32_t count = number_width(layout.type);
    std::uint64_t bits = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
        auto word = words[word_slot(i, count, layout.order)];
        if (layout.order.low_byte_first && layout.type != NumberType::Bit) word = swap_bytes(word);
        bits = bits << 16 | word;
    }
    return number_from_bits(bits, layout.type) * layout.scale + layout.offset;
}

double number_from_bits(std::uint64_t bits, NumberType type) {
    switch (type) {
        case NumberType::Bit:
        case NumberType::U16:
        case NumberType::U32:
            return static_cast<double>(bits);
        case NumberType::I16:
            return static_cast<std::int16_t>(bits);
        case NumberType::I32:
            return static_cast<std::int32_t>(bits);
        case NumberType::U64:
            return static_cast<double>(bits);
        case NumberType::I64:
            return static_cast<double>(static_cast<std::int64_t>(bits));
        case NumberType::F32:
            return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
        case NumberType::F64:
            return std::bit_cast<double>(bits);
    }
    return 0;
}

}  // namespace mblab::device
