#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

// A [[unit.behaviours]] table after loading (docs/profiles.md "Values that move"): which points
// it drives, how their numbers sit in registers, and how the numbers move. The loader guarantees
// every point is mapped, no two behaviours drive the same register, and min < max where used.
namespace mblab::device {

enum class BankKind : std::uint8_t;

// How one value sits in the bank: a bit, or 1, 2 or 4 registers.
enum class NumberType : std::uint8_t { Bit, U16, I16, U32, I32, U64, I64, F32, F64 };

// The registers' order as the letters Modbus tools use: A is the most significant byte.
// ABCD: high word first, high byte first; CDAB: words swapped; BADC: bytes swapped; DCBA: both.
struct ByteOrder {
    bool low_word_first = false;
    bool low_byte_first = false;
};

struct NumberLayout {
    NumberType type = NumberType::U16;
    ByteOrder order;
    // The register holds (value - offset) / scale: a value of 21.5 with scale 0.1 is 215.
    double scale = 1.0;
    double offset = 0.0;
};

enum class BehaviourKind : std::uint8_t {
    Constant,    // value
    Ramp,        // min to max over period, then back to min (sawtooth)
    Sine,        // between min and max, one cycle per period
    RandomWalk,  // from start, a step of at most `step` either way per update, kept in bounds
    Random,      // a new value in [min, max] each update
    Counter,     // start, then + step each update; past max it wraps to min
    Uptime,      // seconds since the device started
    Timestamp,   // seconds since 1970 (the Unix time)
    Follow,      // the raw registers of `source`, as they were `lag` earlier
};

struct BehaviourSpec {
    BehaviourKind kind = BehaviourKind::Constant;
    BankKind bank{};
    std::uint32_t address = 0;
    std::uint32_t points = 1;  // consecutive values, each of the layout's width
    NumberLayout layout;
    std::chrono::milliseconds interval{1000};
    std::chrono::milliseconds period{60'000};
    double value = 0;
    double min = 0;
    double max = 0;
    double step = 1;
    double start = 0;
    BankKind source_bank{};
    std::uint32_t source = 0;
    std::chrono::milliseconds lag{0};
    // A counter past max starts again at min; one that does not wrap stays at max (a SunSpec
    // accumulator, which only increases).
    bool wraps = true;
    // A SunSpec scale factor register in the same bank: each update scales by 10^its value as
    // it is then (a point whose scale factor is not implemented is left alone).
    std::optional<std::uint32_t> scale_factor_at = {};
};

// Registers one value of `type` takes (a bit takes one coil).
std::uint32_t number_width(NumberType type);

}  // namespace mblab::device
