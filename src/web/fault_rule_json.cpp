#include "web/fault_rule_json.hpp"

#include <fmt/format.h>

#include <array>
#include <utility>

#include "protocol/limits.hpp"

namespace mblab::web {

namespace {

using device::FaultAction;
using nlohmann::json;

constexpr std::array<std::pair<const char*, FaultAction>, 5> kActions{{
    {"delay", FaultAction::Delay},
    {"drop", FaultAction::Drop},
    {"exception", FaultAction::Exception},
    {"garbage", FaultAction::Garbage},
    {"close", FaultAction::Close},
}};

const char* action_name(FaultAction action) {
    for (const auto& [name, value] : kActions) {
        if (value == action) return name;
    }
    return "drop";
}

// An integer field inside [low, high]; absent leaves `out` alone.
template <class T>
bool integer_field(const json& object, const char* name, std::int64_t low, std::int64_t high,
                   T& out, std::string& error) {
    if (!object.contains(name)) return true;
    const json& value = object[name];
    if (!value.is_number_integer() || value.get<std::int64_t>() < low ||
        value.get<std::int64_t>() > high) {
        error = fmt::format("{}: expected an integer from {} to {}", name, low, high);
        return false;
    }
    out = static_cast<T>(value.get<std::int64_t>());
    return true;
}

constexpr std::array<const char*, 8> kFields{"action",    "delay_ms",  "exception", "garbage_bytes",
                                             "functions", "addresses", "every",     "probability"};

bool known_field(const std::string& key) {
    for (const char* field : kFields) {
        if (key == field) return true;
    }
    return key == "enabled" || key == "index";
}

}  // namespace

json fault_rule_json(const device::FaultSpec& rule) {
    json out{{"action", action_name(rule.action)}};
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
    for (const auto& [key, value] : object.items()) {
        if (!known_field(key)) {
            error = fmt::format("{}: not a fault rule field", key);
            return false;
        }
    }
    rule = {};
    const json action = object.value("action", json());
    bool found = false;
    for (const auto& [name, value] : kActions) {
        if (action.is_string() && action.get<std::string>() == name) {
            rule.action = value;
            found = true;
        }
    }
    if (!found) {
        error = "action: expected one of delay, drop, exception, garbage, close";
        return false;
    }
    if (rule.action == FaultAction::Delay && !object.contains("delay_ms")) {
        error = "delay_ms: a delay rule needs it, e.g. \"delay_ms\": 500";
        return false;
    }
    std::int64_t delay_ms = 0;
    int exception = static_cast<int>(rule.exception);
    if (!integer_field(object, "delay_ms", 0, 600000, delay_ms, error) ||
        !integer_field(object, "exception", 1, 0xFF, exception, error) ||
        !integer_field(object, "garbage_bytes", 1,
                       static_cast<std::int64_t>(protocol::limits::kMaxPdu), rule.garbage_bytes,
                       error) ||
        !integer_field(object, "every", 1, 1000000, rule.every, error)) {
        return false;
    }
    rule.delay = std::chrono::milliseconds(delay_ms);
    rule.exception = static_cast<protocol::ExceptionCode>(exception);
    if (object.contains("functions")) {
        const json& functions = object["functions"];
        if (!functions.is_array()) {
            error = "functions: expected a list of function codes from 1 to 127";
            return false;
        }
        for (const json& code : functions) {
            if (!code.is_number_integer() || code.get<int>() < 1 || code.get<int>() > 0x7F) {
                error = "functions: expected a list of function codes from 1 to 127";
                return false;
            }
            rule.functions.push_back(code.get<std::uint8_t>());
        }
    }
    if (object.contains("addresses")) {
        const json& range = object["addresses"];
        if (!range.is_array() || range.size() != 2 || !range[0].is_number_integer() ||
            !range[1].is_number_integer() || range[0].get<std::int64_t>() < 0 ||
            range[1].get<std::int64_t>() > 0xFFFF ||
            range[0].get<std::int64_t>() > range[1].get<std::int64_t>()) {
            error = "addresses: expected [first, last], 0 <= first <= last <= 65535";
            return false;
        }
        rule.first_address = range[0].get<std::uint16_t>();
        rule.last_address = range[1].get<std::uint16_t>();
    }
    if (object.contains("probability")) {
        const json& chance = object["probability"];
        if (!chance.is_number() || chance.get<double>() < 0 || chance.get<double>() > 1) {
            error = "probability: expected a number from 0 to 1";
            return false;
        }
        if (object.contains("every")) {
            error = "probability: give either every (every Nth request) or probability";
            return false;
        }
        rule.probability = chance.get<double>();
    }
    return true;
}

}  // namespace mblab::web
