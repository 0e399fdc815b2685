#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "device/profile.hpp"

// A fault rule's fields, their limits and the reasons a rule is refused, kept once for the two
// syntaxes that write one: a profile's [[unit.faults]] table (TOML) and the HTTP API's JSON
// (docs/profiles.md "Fault rules"). A reader only maps its syntax onto RuleField values and puts
// the error where its users look for it (a file's line, a JSON reply).
namespace mblab::device {

// One field's value as a reader found it, whatever the syntax.
struct RuleValue {
    enum class Type : std::uint8_t { Integer, Number, String, List, Other };
    Type type = Type::Other;
    std::int64_t integer = 0;
    double number = 0;             // an Integer's value too
    std::string text;              // a String's text
    std::vector<RuleValue> items;  // a List's elements
    std::string described;         // how the value reads in a message: 42, the string "x", an array
};

struct RuleField {
    std::string name;
    RuleValue value;
};

// Why a rule is refused: the field ("functions", or its element "functions[2]") and the reason.
struct RuleError {
    std::string key;
    std::optional<std::size_t> element;
    std::string message;

    std::string field() const;
};

// The rule `fields` describe, or the first reason it is not one (an unknown field is one).
bool read_fault_rule(std::span<const RuleField> fields, FaultSpec& rule, RuleError& error);

std::string_view fault_action_name(FaultAction action);

}  // namespace mblab::device
