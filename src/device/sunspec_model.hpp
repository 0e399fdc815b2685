#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// A SunSpec information model as the SunSpec Information Model Specification (v1.0, "Model
// definition" and "Point types") defines it and the official JSON model files write it: a top
// group of points, then its groups in order, a group repeated as many times as its count says.
namespace mblab::device {

enum class SunSpecType : std::uint8_t {
    Int16,
    Int32,
    Int64,
    Uint16,
    Uint32,
    Uint64,
    Acc16,
    Acc32,
    Acc64,
    Bitfield16,
    Bitfield32,
    Bitfield64,
    Enum16,
    Enum32,
    Float32,
    Float64,
    String,
    Pad,
    Ipaddr,
    Ipv6addr,
    Eui48,
    Sunssf,
    Count
};

// The JSON name ("uint16") and back.
std::optional<SunSpecType> sunspec_type_named(std::string_view name);
std::string_view sunspec_type_name(SunSpecType type);
// Registers a point of `type` takes; 0 for a string, whose size the model says.
std::uint16_t sunspec_type_size(SunSpecType type);

struct SunSpecSymbol {
    std::string name = {};
    std::int64_t value = 0;
};

struct SunSpecPoint {
    std::string name = {};
    std::string label = {};
    SunSpecType type = SunSpecType::Uint16;
    std::uint16_t size = 1;
    // Registers from the start of the group's instance; in the top group, from the model's ID.
    std::uint32_t offset = 0;
    // The name of the sunssf point that scales this one (in this group or one above); empty when
    // the point is not scaled. An integer scale factor is kept in `fixed_sf` instead.
    std::string sf = {};
    std::optional<int> fixed_sf = {};
    std::string units = {};
    bool writable = false;                   // access RW
    bool mandatory = false;                  // mandatory M
    bool is_static = false;                  // static S
    std::optional<std::int64_t> value = {};  // a fixed value (ID's model id)
    std::vector<SunSpecSymbol> symbols = {};
};

struct SunSpecGroup {
    std::string name = {};
    std::string label = {};
    // A repeating group's count: the name of the point that holds it, or a fixed number; a fixed
    // count of 0 means "as many as fit in the model's length".
    std::string count_point = {};
    std::uint32_t fixed_count = 1;
    std::vector<SunSpecPoint> points = {};
    std::vector<SunSpecGroup> groups = {};
    // Registers of one instance when every repeating group below repeats `fixed_count` times.
    std::uint32_t size = 0;

    bool repeats() const { return !count_point.empty() || fixed_count != 1; }
    const SunSpecPoint* point(std::string_view point_name) const;
};

struct SunSpecModel {
    std::uint16_t id = 0;
    SunSpecGroup group = {};
    // The length L the model declares with no repeating instances beyond fixed counts: registers
    // after ID and L.
    std::uint32_t fixed_length = 0;

    // L when each counted group repeats as `counts` says: by its count point's name, or by the
    // group's own name for a group whose fixed count is 0; a count not given counts 0.
    std::uint32_t length_with(const std::map<std::string, std::uint32_t>& counts) const;
};

bool is_sunspec_enum(SunSpecType type);

// A point's registers (high word first) as one number, and back: the low `size` registers of
// `raw` (registers beyond the fourth are 0).
std::uint64_t sunspec_bits(std::span<const std::uint16_t> words);
std::vector<std::uint16_t> sunspec_words(std::uint64_t raw, std::size_t size);
// Whether an accumulator read as `before` and then `after` went back. Accumulators roll over at
// their type's maximum, so a step forward across the wrap is an increase; only a step of more
// than half the range forward, a step back, is a decrease.
bool sunspec_accumulator_went_back(std::span<const std::uint16_t> before,
                                   std::span<const std::uint16_t> after);

// The value a point holds when the device does not implement it, as its registers.
std::vector<std::uint16_t> not_implemented_words(const SunSpecPoint& point);
bool is_not_implemented(const SunSpecPoint& point, std::span<const std::uint16_t> words);

// A numeric point's raw value from its registers (big-endian words); none for strings, pads and
// addresses.
std::optional<double> sunspec_raw_value(SunSpecType type, std::span<const std::uint16_t> words);
// A string point's text: its bytes up to the first NUL.
std::string sunspec_string(std::span<const std::uint16_t> words);

}  // namespace mblab::device
