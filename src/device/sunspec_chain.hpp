#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "device/profile.hpp"
#include "device/profile_loader.hpp"
#include "device/sunspec_model.hpp"

// A SunSpec device's holding registers built from the model definitions (SunSpec Information
// Model Specification v1.0, "Device Modbus Map"): the "SunS" marker at the base, the common
// model 1, the models listed, the end model 0xFFFF of length 0. Every point the profile gives no
// value holds its type's "not implemented" value. The profile's [unit.sunspec] section
// (docs/sunspec.md) is this, as loaded.
namespace mblab::device {

// A number is an engineering value: a point scaled by a scale factor holds value / 10^sf,
// rounded (sunssf points themselves, counts and enums are raw). A string fills a string point,
// or names one of an enum's symbols.
using SunSpecValue = std::variant<double, std::string>;

struct SunSpecModelValues {
    std::uint16_t id = 0;
    // By point: "W" in the top group, "module[2].DCA" in the second instance of a repeating
    // group, as `mblab sunspec` names them.
    std::map<std::string, SunSpecValue> values = {};
    // The values an RW point takes, as engineering values; beyond them a write answers 03.
    std::map<std::string, std::pair<double, double>> limits = {};
    // Registers of zeros after the model's points, counted in its L: a device whose model is
    // longer than its definition (built wrong on purpose).
    std::uint16_t extra_registers = 0;
};

struct SunSpecChainSpec {
    std::uint32_t base = 40000;
    std::vector<SunSpecModelValues> models = {};  // model 1 first
    // A read or write that takes part of a point of 2 or more registers: answered (false) or
    // refused with exception 02 (true).
    bool split_refused = false;
    // Knobs for devices built wrong on purpose, to test the tester.
    bool end_model = true;            // false: the chain stops after its last model
    bool writes_applied = true;       // false: writes to RW points are answered, not kept
    bool read_only_writable = false;  // true: R points take writes like RW ones
};

// A point as laid, for what drives it by name (a behaviour on it).
struct SunSpecPlacedPoint {
    std::uint32_t address = 0;
    SunSpecType type = SunSpecType::Uint16;
    std::uint16_t size = 1;
    // Its scale factor: a fixed one, or the sunssf point `sf` at `sf_address` with the value the
    // profile gives it (none when it gives none); 0 for a point not scaled.
    std::optional<int> sf = 0;
    std::string sf_name = {};
    std::optional<std::uint32_t> sf_address = {};
    bool given = false;  // the profile gives the point a value
};

struct SunSpecChain {
    std::vector<RangeSpec> ranges = {};  // holding registers, in address order
    std::vector<PointRule> rules = {};   // in address order
    // Per model of the spec, in its order: its points by name ("W", "module[2].DCA").
    std::vector<std::map<std::string, SunSpecPlacedPoint>> points = {};
};

// Lays out the chain; `definitions` holds every model the spec lists. The error is one line
// naming the model and point.
Loaded<SunSpecChain> build_sunspec_chain(const SunSpecChainSpec& spec,
                                         const std::map<std::uint16_t, SunSpecModel>& definitions);

}  // namespace mblab::device
