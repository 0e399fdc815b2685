#include "device/sunspec_behaviours.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <iterator>
#include <set>
#include <sstream>
#include <utility>

#include "device/behaviour_loader.hpp"
#include "device/number_codec.hpp"
#include "device/profile_sections.hpp"

namespace mblab::device {

namespace {

// How a behaviour encodes a point of each type it drives: as the number type of its big-endian
// registers (ABCD), within the raw values the point holds besides its type's "not implemented"
// one (0x8000.. signed, 0xFFFF.. unsigned, 0 for an accumulator, NaN for a float). 64-bit points
// stop at 2^53, the integers a double holds exactly.
struct Encoding {
    SunSpecType type = SunSpecType::Int16;
    NumberType number = NumberType::I16;
    double low = 0;
    double high = 0;
};

constexpr double kExact = 9007199254740992.0;  // 2^53
constexpr Encoding kEncodings[] = {
    {SunSpecType::Int16, NumberType::I16, -32767, 32767},
    {SunSpecType::Uint16, NumberType::U16, 0, 65534},
    {SunSpecType::Acc16, NumberType::U16, 1, 65535},
    {SunSpecType::Int32, NumberType::I32, -2147483647.0, 2147483647.0},
    {SunSpecType::Uint32, NumberType::U32, 0, 4294967294.0},
    {SunSpecType::Acc32, NumberType::U32, 1, 4294967295.0},
    {SunSpecType::Int64, NumberType::I64, -kExact, kExact},
    {SunSpecType::Uint64, NumberType::U64, 0, kExact},
    {SunSpecType::Acc64, NumberType::U64, 1, kExact},
    {SunSpecType::Float32, NumberType::F32, -FLT_MAX, FLT_MAX},
    {SunSpecType::Float64, NumberType::F64, -DBL_MAX, DBL_MAX},
};

const Encoding* encoding_of(SunSpecType type) {
    const auto* found = std::find_if(std::begin(kEncodings), std::end(kEncodings),
                                     [type](const Encoding& e) { return e.type == type; });
    return found == std::end(kEncodings) ? nullptr : found;
}

bool is_accumulator(SunSpecType type) {
    return type == SunSpecType::Acc16 || type == SunSpecType::Acc32 || type == SunSpecType::Acc64;
}

std::string number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

class PointBehaviour {
  public:
    PointBehaviour(Fields& fields, std::string model) : fields_(fields), model_(std::move(model)) {}

    bool load(const std::map<std::string, SunSpecPlacedPoint>& points,
              std::set<std::string>& driven, BehaviourSpec& out) {
        if (!fields_.require("point", "the point it drives, e.g. point = \"W\"") ||
            !fields_.string("point", name_)) {
            return false;
        }
        const auto found = points.find(name_);
        if (found == points.end()) return fail("point", "no point \"" + name_ + "\" to drive");
        const SunSpecPlacedPoint& point = found->second;
        const std::string type(sunspec_type_name(point.type));
        const Encoding* encoding = encoding_of(point.type);
        if (encoding == nullptr) {
            return fail("point", name_ + " is " + type +
                                     "; a behaviour drives int, uint, acc and float points");
        }
        if (point.given) {
            return fail("point", name_ + " has a value in points too; give it one or the other");
        }
        if (!driven.insert(name_).second) {
            return fail("point", name_ + " has a behaviour already; one behaviour drives a point");
        }
        if (!point.sf) {
            return fail("point", name_ + " is scaled by " + point.sf_name +
                                     ", which has no value; give " + point.sf_name +
                                     " one in points");
        }
        out.bank = BankKind::HoldingRegisters;
        out.address = point.address;
        out.layout.type = encoding->number;
        out.layout.scale = std::pow(10.0, *point.sf);
        out.scale_factor_at = point.sf_address;
        if (!load_behaviour_kind(fields_, out)) return false;
        if (out.kind == BehaviourKind::Uptime || out.kind == BehaviourKind::Timestamp ||
            out.kind == BehaviourKind::Follow) {
            return fail("kind", name_ +
                                    ": a SunSpec point takes constant, ramp, sine, random-walk, "
                                    "random or counter");
        }
        const bool accumulator = is_accumulator(point.type);
        if (accumulator && out.kind != BehaviourKind::Counter &&
            out.kind != BehaviourKind::Constant) {
            return fail("kind", name_ + " is an accumulator (" + type +
                                    "), which only increases; use counter or constant");
        }
        if (!load_behaviour_motion(fields_, out)) return false;
        const double low = encoding->low;
        const double high = encoding->high;
        const double scale = out.layout.scale;
        if (out.kind == BehaviourKind::Counter) {
            // By default a counter runs over the values the point holds, not its registers'.
            if (!fields_.has("max")) out.max = high * scale;
            if (!fields_.has("min")) out.min = std::max(low, 0.0) * scale;
            if (!fields_.has("start")) out.start = out.min;
            // An accumulator rolls over at its type's end and starts again at its min, as a
            // meter's register rolls over (a reader counts the step modulo the range); one given
            // a max of its own stops there.
            out.wraps = !accumulator || !fields_.has("max");
            // Below its min a counter would run on to the type's "not implemented" value.
            if (!(out.step > 0)) {
                return fail("step", name_ +
                                        (accumulator ? " is an accumulator (" + type +
                                                           "), which only increases"
                                                     : ": a counter on a point counts up") +
                                        "; give a step above 0");
            }
        }
        return in_range(out, type, low, high);
    }

  private:
    bool fail(std::string_view key, const std::string& message) {
        fields_.fail(key, model_ + ": " + message);
        return false;
    }

    // Every value the behaviour takes, in registers, is one the point holds.
    bool in_range(const BehaviourSpec& spec, const std::string& type, double low, double high) {
        const bool constant = spec.kind == BehaviourKind::Constant;
        const bool started =
            spec.kind == BehaviourKind::Counter || spec.kind == BehaviourKind::RandomWalk;
        const double lowest =
            constant ? spec.value : std::min(spec.min, started ? spec.start : spec.min);
        const double highest = constant ? spec.value : spec.max;
        const double scale = spec.layout.scale;
        if (std::nearbyint(lowest / scale) >= low && std::nearbyint(highest / scale) <= high) {
            return true;
        }
        return fail(constant ? "value" : "max", name_ + " (" + type + ", scale " + number(scale) +
                                                    ") holds " + number(low * scale) + ".." +
                                                    number(high * scale) + "; " + number(lowest) +
                                                    ".." + number(highest) + " does not fit");
    }

    Fields& fields_;
    std::string model_;
    std::string name_;
};

// The value a behaviour starts from (a random one its range's middle until it draws).
double first_value(const BehaviourSpec& spec) {
    switch (spec.kind) {
        case BehaviourKind::Constant:
            return spec.value;
        case BehaviourKind::Ramp:
            return spec.min;
        case BehaviourKind::RandomWalk:
        case BehaviourKind::Counter:
            return spec.start;
        default:
            return (spec.min + spec.max) / 2;
    }
}

}  // namespace

bool load_sunspec_behaviours(Fields& model, std::uint16_t id,
                             const std::map<std::string, SunSpecPlacedPoint>& points,
                             std::vector<RangeSpec>& ranges, std::vector<BehaviourSpec>& out) {
    std::set<std::string> driven;
    return each_table(model, "behaviours", [&](const toml::table& t, const std::string& path) {
        Fields fields(t, path, model.errors());
        PointBehaviour behaviour(fields, "model " + std::to_string(id));
        BehaviourSpec spec;
        if (!behaviour.load(points, driven, spec)) return false;
        fields.finish();
        // Each point is a range of its own.
        const auto range = std::find_if(ranges.begin(), ranges.end(), [&](const RangeSpec& r) {
            return r.start == spec.address;
        });
        if (range != ranges.end()) {
            const auto words = encode_number(first_value(spec), spec.layout);
            range->values.assign(words.view().begin(), words.view().end());
        }
        out.push_back(spec);
        return !fields.failed();
    });
}

}  // namespace mblab::device
