// The fault rule schema read directly, without a syntax: values become the rule's fields, and
// the first bad field stops the reading with its reason.
#include <gtest/gtest.h>

#include "device/fault_rule_schema.hpp"

namespace mblab::test {
namespace {

using device::RuleField;
using device::RuleValue;

RuleValue integer(std::int64_t value) {
    RuleValue out;
    out.type = RuleValue::Type::Integer;
    out.integer = value;
    out.number = static_cast<double>(value);
    out.described = std::to_string(value);
    return out;
}

RuleValue text(std::string value) {
    RuleValue out;
    out.type = RuleValue::Type::String;
    out.described = "the string \"" + value + "\"";
    out.text = std::move(value);
    return out;
}

RuleValue list(std::vector<RuleValue> items) {
    RuleValue out;
    out.type = RuleValue::Type::List;
    out.items = std::move(items);
    out.described = "an array";
    return out;
}

TEST(FaultRuleSchema, ReadsEveryField) {
    const std::vector<RuleField> fields{{"action", text("garbage")},
                                        {"garbage_bytes", integer(12)},
                                        {"functions", list({integer(4), integer(3)})},
                                        {"addresses", list({integer(5), integer(9)})},
                                        {"every", integer(4)}};
    device::FaultSpec rule;
    device::RuleError error;
    ASSERT_TRUE(device::read_fault_rule(fields, rule, error)) << error.message;
    EXPECT_EQ(rule.action, device::FaultAction::Garbage);
    EXPECT_EQ(rule.garbage_bytes, 12);
    EXPECT_EQ(rule.functions, (std::vector<std::uint8_t>{4, 3}));
    EXPECT_EQ(rule.first_address, 5);
    EXPECT_EQ(rule.last_address, 9);
    EXPECT_EQ(rule.every, 4U);
    EXPECT_EQ(device::fault_action_name(rule.action), "garbage");
}

TEST(FaultRuleSchema, TheFirstBadFieldStopsTheReading) {
    // delay_ms comes before functions in the schema's order, whatever the order given.
    const std::vector<RuleField> fields{
        {"functions", list({integer(0)})}, {"action", text("delay")}, {"delay_ms", integer(-1)}};
    device::FaultSpec rule;
    device::RuleError error;
    ASSERT_FALSE(device::read_fault_rule(fields, rule, error));
    EXPECT_EQ(error.field(), "delay_ms");
    EXPECT_EQ(error.message, "expected an integer from 0 to 600000, got -1");
}

TEST(FaultRuleSchema, AnElementIsNamedByItsIndex) {
    const std::vector<RuleField> fields{{"action", text("drop")},
                                        {"functions", list({integer(3), text("x")})}};
    device::FaultSpec rule;
    device::RuleError error;
    ASSERT_FALSE(device::read_fault_rule(fields, rule, error));
    EXPECT_EQ(error.key, "functions");
    EXPECT_EQ(error.element, 1U);
    EXPECT_EQ(error.field(), "functions[1]");
    EXPECT_EQ(error.message, "expected an integer, got the string \"x\"");
}

TEST(FaultRuleSchema, AnIntegerIsAProbability) {
    const std::vector<RuleField> fields{{"action", text("close")}, {"probability", integer(0)}};
    device::FaultSpec rule;
    device::RuleError error;
    ASSERT_TRUE(device::read_fault_rule(fields, rule, error)) << error.message;
    EXPECT_EQ(rule.probability, 0.0);
    EXPECT_EQ(rule.every, 0U);
}

}  // namespace
}  // namespace mblab::test
