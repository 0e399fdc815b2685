#include "device/behaviour_loader.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "device/number_codec.hpp"
#include "device/profile_loader.hpp"
#include "device/profile_sections.hpp"

// [[unit.behaviours]]: values that move (docs/profiles.md "Values that move").
namespace mblab::device {

namespace {

constexpr double kHuge = 1e300;
constexpr std::int64_t kMaxIntervalMs = 24LL * 3600 * 1000;

bool choose_bank(Fields& fields, std::string_view key, BankKind& out) {
    return fields.choice<BankKind>(key, out,
                                   {{"coils", BankKind::Coils},
                                    {"discrete_inputs", BankKind::DiscreteInputs},
                                    {"holding_registers", BankKind::HoldingRegisters},
                                    {"input_registers", BankKind::InputRegisters}});
}

bool load_layout(Fields& fields, BankKind bank, bool with_scaling, NumberLayout& out) {
    if (is_bit_bank(bank)) {
        out.type = NumberType::Bit;
        fields.choice<NumberType>("type", out.type, {{"bit", NumberType::Bit}});
    } else if (std::string name; fields.string("type", name)) {
        if (const auto type = register_type_named(name)) {
            out.type = *type;
        } else {
            fields.fail("type",
                        "expected one of " + register_type_names() + ", got \"" + name + "\"");
        }
    }
    if (!with_scaling) return !fields.failed();
    fields.choice<ByteOrder>("order", out.order,
                             {{"ABCD", ByteOrder{false, false}},
                              {"CDAB", ByteOrder{true, false}},
                              {"BADC", ByteOrder{false, true}},
                              {"DCBA", ByteOrder{true, true}}});
    if (fields.number("scale", out.scale, -kHuge, kHuge) && out.scale == 0) {
        fields.fail("scale", "expected a number other than 0 (the register holds value / scale)");
    }
    fields.number("offset", out.offset, -kHuge, kHuge);
    return !fields.failed();
}

bool milliseconds(Fields& fields, std::string_view key, std::int64_t min,
                  std::chrono::milliseconds& out) {
    std::int64_t ms = 0;
    if (!fields.integer(key, ms, min, kMaxIntervalMs)) return false;
    out = std::chrono::milliseconds(ms);
    return true;
}

// min and max, both required, min below max.
bool bounds(Fields& fields, std::string_view hint, BehaviourSpec& out) {
    if (!fields.require("min", hint) || !fields.require("max", hint)) return false;
    fields.number("min", out.min, -kHuge, kHuge);
    fields.number("max", out.max, -kHuge, kHuge);
    if (!fields.failed() && !(out.min < out.max)) {
        fields.fail("max",
                    "expected a number above min (" + describe_node(*fields.get("min")) + ")");
    }
    return !fields.failed();
}

// Where behaviours may go and where they already are, per bank. Asked of every range and every
// earlier behaviour, a behaviour on each of 131,072 registers took 26 s to load.
class Placement {
  public:
    explicit Placement(const UnitSpec& unit) {
        for (std::size_t bank = 0; bank < kBankKinds; ++bank) {
            for (const auto& range : unit.banks[bank])
                spans_[bank].emplace_back(range.start, range.start + range.count);
            std::sort(spans_[bank].begin(), spans_[bank].end());
        }
    }

    // Whether [start, start + count) lies in the bank's ranges without a hole.
    bool mapped(BankKind bank, std::uint32_t start, std::uint32_t count) const {
        const auto& spans = spans_[static_cast<std::size_t>(bank)];
        for (std::uint32_t next = start; next < start + count;) {
            auto it = std::upper_bound(spans.begin(), spans.end(), next,
                                       [](std::uint32_t a, const auto& s) { return a < s.first; });
            if (it == spans.begin() || next >= (--it)->second) return false;
            next = it->second;
        }
        return true;
    }

    // The first behaviour (its index) already driving an address of [start, start + count).
    std::optional<std::size_t> driven(BankKind bank, std::uint32_t start,
                                      std::uint32_t count) const {
        const auto& owners = owners_[static_cast<std::size_t>(bank)];
        std::optional<std::size_t> first;
        for (std::uint32_t a = start; a < start + count && a < owners.size(); ++a) {
            if (owners[a] != 0 && (!first || owners[a] - 1 < *first)) first = owners[a] - 1;
        }
        return first;
    }

    void drive(BankKind bank, std::uint32_t start, std::uint32_t count, std::size_t index) {
        auto& owners = owners_[static_cast<std::size_t>(bank)];
        if (owners.empty()) owners.assign(0x10000, 0);
        for (std::uint32_t a = start; a < start + count; ++a)
            owners[a] = static_cast<std::uint32_t>(index + 1);
    }

  private:
    std::array<std::vector<std::pair<std::uint32_t, std::uint32_t>>, kBankKinds> spans_;  // [)
    std::array<std::vector<std::uint32_t>, kBankKinds> owners_;  // 1 + index, 0: none
};

std::string addresses(std::uint32_t start, std::uint32_t count) {
    return std::to_string(start) + ".." + std::to_string(start + count - 1);
}

bool check_placement(Fields& fields, const Placement& placement,
                     const std::vector<BehaviourSpec>& before, const BehaviourSpec& spec) {
    const std::uint32_t count = spec.points * number_width(spec.layout.type);
    if (spec.address + count > 65536 || !placement.mapped(spec.bank, spec.address, count)) {
        fields.fail("address", std::string(bank_key(spec.bank)) + " " +
                                   addresses(spec.address, count) +
                                   " are not all in the unit's ranges; add a range for them");
        return false;
    }
    if (spec.kind == BehaviourKind::Follow &&
        (spec.source + count > 65536 || !placement.mapped(spec.source_bank, spec.source, count))) {
        fields.fail("source", std::string(bank_key(spec.source_bank)) + " " +
                                  addresses(spec.source, count) +
                                  " are not all in the unit's ranges; add a range for them");
        return false;
    }
    if (const auto i = placement.driven(spec.bank, spec.address, count)) {
        const auto& other = before[*i];
        const std::uint32_t other_count = other.points * number_width(other.layout.type);
        fields.fail("address", addresses(spec.address, count) + " overlap behaviours[" +
                                   std::to_string(*i) + "] (" +
                                   addresses(other.address, other_count) +
                                   "); one behaviour drives a register");
        return false;
    }
    return true;
}

}  // namespace

bool load_behaviour_kind(Fields& fields, BehaviourSpec& out) {
    if (!fields.require("kind",
                        "one of constant, ramp, sine, random-walk, random, counter, "
                        "uptime, timestamp, follow")) {
        return false;
    }
    fields.choice<BehaviourKind>("kind", out.kind,
                                 {{"constant", BehaviourKind::Constant},
                                  {"ramp", BehaviourKind::Ramp},
                                  {"sine", BehaviourKind::Sine},
                                  {"random-walk", BehaviourKind::RandomWalk},
                                  {"random", BehaviourKind::Random},
                                  {"counter", BehaviourKind::Counter},
                                  {"uptime", BehaviourKind::Uptime},
                                  {"timestamp", BehaviourKind::Timestamp},
                                  {"follow", BehaviourKind::Follow}});
    if (fields.failed()) return false;
    milliseconds(fields, "interval_ms", 10, out.interval);
    return !fields.failed();
}

bool load_behaviour_motion(Fields& fields, BehaviourSpec& out) {
    switch (out.kind) {
        case BehaviourKind::Constant:
            if (!fields.require("value", "the value to hold, e.g. value = 42")) return false;
            fields.number("value", out.value, -kHuge, kHuge);
            break;
        case BehaviourKind::Ramp:
        case BehaviourKind::Sine:
            if (!bounds(fields, "the bounds of the wave, e.g. min = 0 and max = 100", out)) {
                return false;
            }
            if (!fields.require("period_ms", "the time of one cycle, e.g. period_ms = 60000")) {
                return false;
            }
            milliseconds(fields, "period_ms", 1, out.period);
            break;
        case BehaviourKind::RandomWalk:
            if (!bounds(fields, "the bounds of the walk, e.g. min = 0 and max = 100", out)) {
                return false;
            }
            if (!fields.require("step", "the largest move per update, e.g. step = 0.5")) {
                return false;
            }
            fields.number("step", out.step, 0, kHuge);
            out.start = (out.min + out.max) / 2;
            fields.number("start", out.start, out.min, out.max);
            break;
        case BehaviourKind::Random:
            return bounds(fields, "the bounds of the values, e.g. min = 0 and max = 100", out);
        case BehaviourKind::Counter:
            out.min = 0;
            out.max = largest_raw(out.layout.type) * out.layout.scale + out.layout.offset;
            fields.number("min", out.min, -kHuge, kHuge);
            fields.number("max", out.max, out.min, kHuge);
            out.start = out.min;
            fields.number("start", out.start, out.min, out.max);
            fields.number("step", out.step, -kHuge, kHuge);
            break;
        case BehaviourKind::Uptime:
        case BehaviourKind::Timestamp:
            break;
        case BehaviourKind::Follow:
            if (!fields.require("source", "the first address to follow, e.g. source = 10")) {
                return false;
            }
            fields.integer_as("source", out.source, 0, 0xFFFF);
            out.source_bank = out.bank;
            choose_bank(fields, "source_bank", out.source_bank);
            milliseconds(fields, "lag_ms", 0, out.lag);
            if (!fields.failed() && is_bit_bank(out.source_bank) != is_bit_bank(out.bank)) {
                fields.fail("source_bank",
                            "a follower copies registers from registers and bits "
                            "from bits");
            }
            break;
    }
    return !fields.failed();
}

bool load_behaviours(Fields& unit, const UnitSpec& spec, std::vector<BehaviourSpec>& out) {
    Placement placement(spec);
    // Behaviours already there (on SunSpec points) hold their registers too.
    for (std::size_t i = 0; i < out.size(); ++i)
        placement.drive(out[i].bank, out[i].address,
                        out[i].points * number_width(out[i].layout.type), i);
    return each_table(unit, "behaviours", [&](const toml::table& t, const std::string& path) {
        Fields fields(t, path, unit.errors());
        BehaviourSpec behaviour;
        behaviour.bank = BankKind::HoldingRegisters;
        if (!load_behaviour_kind(fields, behaviour)) return false;
        choose_bank(fields, "bank", behaviour.bank);
        if (!fields.require("address", "the first address it drives, e.g. address = 0")) {
            return false;
        }
        fields.integer_as("address", behaviour.address, 0, 0xFFFF);
        fields.integer_as("count", behaviour.points, 1, 0x10000);
        if (fields.failed()) return false;
        if (!load_layout(fields, behaviour.bank, behaviour.kind != BehaviourKind::Follow,
                         behaviour.layout) ||
            !load_behaviour_motion(fields, behaviour) ||
            !check_placement(fields, placement, out, behaviour)) {
            return false;
        }
        fields.finish();
        placement.drive(behaviour.bank, behaviour.address,
                        behaviour.points * number_width(behaviour.layout.type), out.size());
        out.push_back(behaviour);
        return !fields.failed();
    });
}

}  // namespace mblab::device
