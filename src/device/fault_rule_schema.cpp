#include "device/fault_rule_schema.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

using Type = RuleValue::Type;

constexpr std::array<std::pair<std::string_view, FaultAction>, 5> kActions{{
    {"delay", FaultAction::Delay},
    {"drop", FaultAction::Drop},
    {"exception", FaultAction::Exception},
    {"garbage", FaultAction::Garbage},
    {"close", FaultAction::Close},
}};

constexpr std::array<std::string_view, 8> kFields{"action",        "delay_ms",   "exception",
                                                  "garbage_bytes", "functions",  "addresses",
                                                  "every",         "probability"};

struct Limits {
    std::int64_t min;
    std::int64_t max;
};
constexpr Limits kDelayMs{0, 600000};
constexpr Limits kException{1, 0xFF};
constexpr Limits kGarbageBytes{1, static_cast<std::int64_t>(protocol::limits::kMaxPdu)};
constexpr Limits kFunction{1, 0x7F};
constexpr Limits kAddress{0, 0xFFFF};
constexpr Limits kEvery{1, 1000000};

std::string join(auto names) {
    std::string out;
    for (std::string_view name : names) {
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out;
}

std::string action_names() {
    std::vector<std::string_view> names;
    for (const auto& [name, action] : kActions)
        names.push_back(name);
    return join(names);
}

// Reads the fields of one rule, stopping at the first error.
class RuleReader {
  public:
    RuleReader(std::span<const RuleField> fields, RuleError& error)
        : fields_(fields), error_(error) {}

    const RuleValue* find(std::string_view key) const {
        const auto it = std::find_if(fields_.begin(), fields_.end(),
                                     [&](const RuleField& f) { return f.name == key; });
        return it == fields_.end() ? nullptr : &it->value;
    }
    bool fail(std::string_view key, std::string message,
              std::optional<std::size_t> element = std::nullopt) {
        error_ = {std::string(key), element, std::move(message)};
        return false;
    }

    // Absent: true and `out` untouched. `element` names a list's element in the error.
    bool integer(std::string_view key, const RuleValue* value, Limits limits, std::int64_t& out,
                 std::optional<std::size_t> element = std::nullopt) {
        if (!value) return true;
        if (value->type != Type::Integer)
            return fail(key, "expected an integer, got " + value->described, element);
        if (value->integer < limits.min || value->integer > limits.max) {
            return fail(key,
                        "expected an integer from " + std::to_string(limits.min) + " to " +
                            std::to_string(limits.max) + ", got " + std::to_string(value->integer),
                        element);
        }
        out = value->integer;
        return true;
    }
    template <class T>
    bool integer_as(std::string_view key, Limits limits, T& out) {
        std::int64_t value = static_cast<std::int64_t>(out);
        if (!integer(key, find(key), limits, value)) return false;
        out = static_cast<T>(value);
        return true;
    }
    const std::vector<RuleValue>* list(std::string_view key) {
        const RuleValue* value = find(key);
        if (!value) return nullptr;
        if (value->type != Type::List) {
            fail(key, "expected an array, got " + value->described);
            return nullptr;
        }
        return &value->items;
    }

  private:
    std::span<const RuleField> fields_;
    RuleError& error_;
};

bool read_action(RuleReader& in, FaultSpec& rule) {
    const RuleValue* action = in.find("action");
    if (!action) return in.fail("action", "missing key; expected one of " + action_names());
    if (action->type != Type::String)
        return in.fail("action", "expected a string, got " + action->described);
    for (const auto& [name, value] : kActions) {
        if (name == action->text) {
            rule.action = value;
            return true;
        }
    }
    return in.fail("action",
                   "expected one of " + action_names() + ", got \"" + action->text + "\"");
}

bool read_functions(RuleReader& in, FaultSpec& rule) {
    const RuleValue* given = in.find("functions");
    if (!given) return true;
    const auto* items = in.list("functions");
    if (!items) return false;
    std::vector<std::int64_t> codes;
    for (std::size_t i = 0; i < items->size(); ++i) {
        std::int64_t code = 0;
        if (!in.integer("functions", &(*items)[i], kFunction, code, i)) return false;
        codes.push_back(code);
    }
    std::vector<std::int64_t> sorted = codes;
    std::sort(sorted.begin(), sorted.end());
    const auto twin = std::adjacent_find(sorted.begin(), sorted.end());
    if (twin != sorted.end())
        return in.fail("functions", "the value " + std::to_string(*twin) + " appears twice");
    rule.functions.assign(codes.begin(), codes.end());
    return true;
}

bool read_addresses(RuleReader& in, FaultSpec& rule) {
    if (!in.find("addresses")) return true;
    const auto* pair = in.list("addresses");
    if (!pair) return false;
    if (pair->size() != 2) {
        return in.fail("addresses", "expected two integers [first, last], got " +
                                        std::to_string(pair->size()) + " elements");
    }
    std::int64_t first = 0;
    std::int64_t last = 0;
    if (!in.integer("addresses", &(*pair)[0], kAddress, first, 0) ||
        !in.integer("addresses", &(*pair)[1], kAddress, last, 1)) {
        return false;
    }
    if (first > last) {
        return in.fail("addresses", "the first value " + std::to_string(first) +
                                        " is greater than the last " + std::to_string(last));
    }
    rule.first_address = static_cast<std::uint16_t>(first);
    rule.last_address = static_cast<std::uint16_t>(last);
    return true;
}

bool read_probability(RuleReader& in, FaultSpec& rule) {
    const RuleValue* chance = in.find("probability");
    if (!chance) return true;
    if (chance->type != Type::Integer && chance->type != Type::Number)
        return in.fail("probability", "expected a number, got " + chance->described);
    if (!(chance->number >= 0.0 && chance->number <= 1.0))
        return in.fail("probability", "expected a number from 0 to 1, got " + chance->described);
    if (in.find("every"))
        return in.fail("probability", "give either every (every Nth request) or probability");
    rule.probability = chance->number;
    return true;
}

}  // namespace

std::string RuleError::field() const {
    return element ? key + "[" + std::to_string(*element) + "]" : key;
}

bool read_fault_rule(std::span<const RuleField> fields, FaultSpec& rule, RuleError& error) {
    RuleReader in(fields, error);
    rule = {};
    if (!read_action(in, rule)) return false;
    if (rule.action == FaultAction::Delay && !in.find("delay_ms")) {
        return in.fail("delay_ms",
                       "missing key; a delay rule needs it: how long to hold the answer, in "
                       "milliseconds");
    }
    std::int64_t delay_ms = 0;
    auto exception = static_cast<std::int64_t>(rule.exception);
    if (!in.integer("delay_ms", in.find("delay_ms"), kDelayMs, delay_ms) ||
        !in.integer("exception", in.find("exception"), kException, exception) ||
        !in.integer_as("garbage_bytes", kGarbageBytes, rule.garbage_bytes) ||
        !read_functions(in, rule) || !read_addresses(in, rule) ||
        !in.integer_as("every", kEvery, rule.every) || !read_probability(in, rule)) {
        return false;
    }
    rule.delay = std::chrono::milliseconds(delay_ms);
    rule.exception = static_cast<protocol::ExceptionCode>(exception);
    for (const RuleField& field : fields) {
        if (std::find(kFields.begin(), kFields.end(), field.name) == kFields.end())
            return in.fail(field.name, "unknown key; expected one of " + join(kFields));
    }
    return true;
}

std::string_view fault_action_name(FaultAction action) {
    for (const auto& [name, value] : kActions) {
        if (value == action) return name;
    }
    return "drop";
}

}  // namespace mblab::device
