#include "web/fault_rule_json.hpp"

#include <cstdint>
#include <limits>
#include <vector>

#include "device/fault_rule_schema.hpp"

namespace mblab::web {

namespace {

using device::FaultAction;
using device::RuleValue;
using nlohmann::json;

std::string describe(const json& value) {
    switch (value.type()) {
        case json::value_t::string:
            return "the string " + value.dump();
        case json::value_t::array:
            return "an array";
        case json::value_t::object:
            return "an object";
        default:
            return value.dump();
    }
}

constexpr auto kMaxInteger = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());

// A JSON value as the fault rule schema reads it.
RuleValue rule_value(const json& value) {
    RuleValue out;
    out.described = describe(value);
    if (value.is_number_integer()) {
        out.type = RuleValue::Type::Integer;
        // A value past int64's range is out of every limit anyway.
        out.integer = value.is_number_unsigned() && value.get<std::uint64_t>() > kMaxInteger
                          ? static_cast<std::int64_t>(kMaxInteger)
                          : value.get<std::int64_t>();
        out.number = static_cast<double>(out.integer);
    } else if (value.is_number()) {
        out.type = RuleValue::Type::Number;
        out.number = value.get<double>();
    } else if (value.is_string()) {
        out.type = RuleValue::Type::String;
        out.text = value.get<std::string>();
    } else if (value.is_array()) {
        out.type = RuleValue::Type::List;
        for (const json& element : value)
            out.items.push_back(rule_value(element));
    }
    return out;
}

}  // namespace

json fault_rule_json(const device::FaultSpec& rule) {
    json out{{"action", device::fault_action_name(rule.action)}};
    if (rule.action == FaultAction::Delay) out["delay_ms"] = rule.delay.count();
    if (rule.action == FaultAction::Exception) out["exception"] = static_cast<int>(rule.exception);
    if (rule.action == FaultAction::Garbage) out["garbage_bytes"] = rule.garbage_bytes;
    if (!rule.functions.empty()) out["functions"] = rule.functions;
    if (rule.first_address) out["addresses"] = {*rule.first_address, *rule.last_address};
    if (rule.every > 0) {
        out["every"] = rule.every;
    } else {
        out["probability"] = rule.probability;
    }
    return out;
}

bool parse_fault_rule(const json& object, device::FaultSpec& rule, std::string& error) {
    if (!object.is_object()) {
        error = "a fault rule is a JSON object";
        return false;
    }
    std::vector<device::RuleField> fields;
    for (const auto& [key, value] : object.items()) {
        // The API's own fields, beside the rule: its place in the list and whether it is on.
        if (key == "enabled" || key == "index") continue;
        fields.push_back({key, rule_value(value)});
    }
    device::RuleError refusal;
    if (device::read_fault_rule(fields, rule, refusal)) return true;
    error = refusal.field() + ": " + refusal.message;
    return false;
}

}  // namespace mblab::web
