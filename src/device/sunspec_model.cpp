#include "device/sunspec_model.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <utility>

#include "device/number_codec.hpp"

namespace mblab::device {
namespace {

// Each type's name, size in registers, "not implemented" value in its width (Information Model
// Specification, "Point types": accumulators use 0, strings and addresses all zero bits) and the
// register type its value reads as (none for strings and addresses).
struct TypeInfo {
    SunSpecType type;
    std::string_view name;
    std::uint16_t size;
    std::uint64_t not_implemented;
    std::optional<NumberType> number;
};

constexpr std::array<TypeInfo, 23> kTypes{{
    {SunSpecType::Int16, "int16", 1, 0x8000, NumberType::I16},
    {SunSpecType::Int32, "int32", 2, 0x80000000, NumberType::I32},
    {SunSpecType::Int64, "int64", 4, 0x8000000000000000, NumberType::I64},
    {SunSpecType::Uint16, "uint16", 1, 0xFFFF, NumberType::U16},
    {SunSpecType::Uint32, "uint32", 2, 0xFFFFFFFF, NumberType::U32},
    {SunSpecType::Uint64, "uint64", 4, 0xFFFFFFFFFFFFFFFF, NumberType::U64},
    {SunSpecType::Acc16, "acc16", 1, 0, NumberType::U16},
    {SunSpecType::Acc32, "acc32", 2, 0, NumberType::U32},
    {SunSpecType::Acc64, "acc64", 4, 0, NumberType::U64},
    {SunSpecType::Bitfield16, "bitfield16", 1, 0xFFFF, NumberType::U16},
    {SunSpecType::Bitfield32, "bitfield32", 2, 0xFFFFFFFF, NumberType::U32},
    {SunSpecType::Bitfield64, "bitfield64", 4, 0xFFFFFFFFFFFFFFFF, NumberType::U64},
    {SunSpecType::Enum16, "enum16", 1, 0xFFFF, NumberType::U16},
    {SunSpecType::Enum32, "enum32", 2, 0xFFFFFFFF, NumberType::U32},
    {SunSpecType::Float32, "float32", 2, 0x7FC00000, NumberType::F32},
    {SunSpecType::Float64, "float64", 4, 0x7FF8000000000000, NumberType::F64},
    {SunSpecType::String, "string", 0, 0, std::nullopt},
    {SunSpecType::Pad, "pad", 1, 0x8000, std::nullopt},
    {SunSpecType::Ipaddr, "ipaddr", 2, 0, std::nullopt},
    {SunSpecType::Ipv6addr, "ipv6addr", 8, 0, std::nullopt},
    {SunSpecType::Eui48, "eui48", 4, 0xFFFFFFFFFFFF, std::nullopt},
    {SunSpecType::Sunssf, "sunssf", 1, 0x8000, NumberType::I16},
    {SunSpecType::Count, "count", 1, 0xFFFF, NumberType::U16},
}};

const TypeInfo& info(SunSpecType type) {
    return kTypes[static_cast<std::size_t>(type)];
}

std::uint32_t group_length(const SunSpecGroup& group,
                           const std::map<std::string, std::uint32_t>& counts) {
    std::uint32_t length = 0;
    for (const SunSpecPoint& point : group.points)
        length += point.size;
    for (const SunSpecGroup& child : group.groups) {
        std::uint32_t times = child.fixed_count;
        if (!child.count_point.empty() || child.fixed_count == 0) {
            const auto found =
                counts.find(child.count_point.empty() ? child.name : child.count_point);
            times = found == counts.end() ? 0 : found->second;
        }
        length += times * group_length(child, counts);
    }
    return length;
}

}  // namespace

std::optional<SunSpecType> sunspec_type_named(std::string_view name) {
    for (const TypeInfo& info : kTypes) {
        if (info.name == name) return info.type;
    }
    return std::nullopt;
}

std::string_view sunspec_type_name(SunSpecType type) {
    return info(type).name;
}

std::uint16_t sunspec_type_size(SunSpecType type) {
    return info(type).size;
}

const SunSpecPoint* SunSpecGroup::point(std::string_view point_name) const {
    for (const SunSpecPoint& candidate : points) {
        if (candidate.name == point_name) return &candidate;
    }
    return nullptr;
}

std::uint32_t SunSpecModel::length_with(const std::map<std::string, std::uint32_t>& counts) const {
    // ID and L precede what L counts.
    return group_length(group, counts) - 2;
}

bool is_sunspec_enum(SunSpecType type) {
    return type == SunSpecType::Enum16 || type == SunSpecType::Enum32;
}

std::uint64_t sunspec_bits(std::span<const std::uint16_t> words) {
    std::uint64_t raw = 0;
    for (std::uint16_t word : words)
        raw = (raw << 16) | word;
    return raw;
}

bool sunspec_accumulator_went_back(std::span<const std::uint16_t> before,
                                   std::span<const std::uint16_t> after) {
    const std::size_t bits = 16 * std::min<std::size_t>(before.size(), 4);
    const std::uint64_t range = bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
    const std::uint64_t forward = (sunspec_bits(after) - sunspec_bits(before)) & range;
    return forward > range / 2;
}

std::vector<std::uint16_t> sunspec_words(std::uint64_t raw, std::size_t size) {
    std::vector<std::uint16_t> words(size, 0);
    for (std::size_t i = 0; i < words.size() && i < 4; ++i)
        words[words.size() - 1 - i] = static_cast<std::uint16_t>(raw >> (16 * i));
    return words;
}

std::vector<std::uint16_t> not_implemented_words(const SunSpecPoint& point) {
    return sunspec_words(info(point.type).not_implemented, point.size);
}

bool is_not_implemented(const SunSpecPoint& point, std::span<const std::uint16_t> words) {
    const std::vector<std::uint16_t> expected = not_implemented_words(point);
    return words.size() == expected.size() &&
           std::equal(words.begin(), words.end(), expected.begin());
}

std::optional<double> sunspec_raw_value(SunSpecType type, std::span<const std::uint16_t> words) {
    const std::optional<NumberType> number = info(type).number;
    if (!number) return std::nullopt;
    return number_from_bits(sunspec_bits(words), *number);
}

std::string sunspec_string(std::span<const std::uint16_t> words) {
    std::string text;
    for (std::uint16_t word : words) {
        for (int shift : {8, 0}) {
            const char c = static_cast<char>((word >> shift) & 0xFF);
            if (c == '\0') return text;
            text.push_back(c);
        }
    }
    return text;
}

}  // namespace mblab::device
