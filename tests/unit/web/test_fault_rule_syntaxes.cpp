// One fault rule schema behind both syntaxes: the same bad rule, written as a profile's
// [[unit.faults]] table and as the HTTP API's JSON, is refused for the same reason at the same
// field, and the same good rule reads the same.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "device/profile_loader.hpp"
#include "web/fault_rule_json.hpp"

namespace mblab::test {
namespace {

struct SameRule {
    std::string_view toml;  // the keys of one [[unit.faults]] table
    std::string_view json;
    std::string_view error;  // "field: reason", empty for a good rule
};

constexpr std::string_view kUnit = "[[unit]]\nid = 1\n[[unit.faults]]\n";
constexpr std::string_view kRulePath = "unit[0].faults[0].";

// The TOML reader's error without "FILE:LINE: unit[0].faults[0]." in front.
std::string toml_error(std::string_view keys, device::FaultSpec& rule) {
    auto loaded = device::parse_profile(std::string(kUnit) + std::string(keys), "t.toml");
    if (loaded) {
        rule = loaded.value().units.at(0).faults.at(0);
        return "";
    }
    const std::string& error = loaded.error();
    const auto at = error.find(kRulePath);
    return at == std::string::npos ? error : error.substr(at + kRulePath.size());
}

std::string json_error(std::string_view text, device::FaultSpec& rule) {
    std::string error;
    return web::parse_fault_rule(nlohmann::json::parse(text), rule, error) ? "" : error;
}

class FaultRuleSyntaxes : public ::testing::TestWithParam<SameRule> {};

TEST_P(FaultRuleSyntaxes, GiveTheSameVerdict) {
    device::FaultSpec from_toml;
    device::FaultSpec from_json;
    EXPECT_EQ(toml_error(GetParam().toml, from_toml), GetParam().error);
    EXPECT_EQ(json_error(GetParam().json, from_json), GetParam().error);
    if (!GetParam().error.empty()) return;
    EXPECT_EQ(web::fault_rule_json(from_toml), web::fault_rule_json(from_json));
}

INSTANTIATE_TEST_SUITE_P(
    Rules, FaultRuleSyntaxes,
    ::testing::Values(
        SameRule{"every = 2\n", R"({"every":2})",
                 "action: missing key; expected one of delay, drop, exception, garbage, close"},
        SameRule{"action = \"explode\"\n", R"({"action":"explode"})",
                 "action: expected one of delay, drop, exception, garbage, close, got "
                 "\"explode\""},
        SameRule{"action = 3\n", R"({"action":3})", "action: expected a string, got 3"},
        SameRule{"action = \"delay\"\n", R"({"action":"delay"})",
                 "delay_ms: missing key; a delay rule needs it: how long to hold the answer, in "
                 "milliseconds"},
        SameRule{"action = \"delay\"\ndelay_ms = 600001\n",
                 R"({"action":"delay","delay_ms":600001})",
                 "delay_ms: expected an integer from 0 to 600000, got 600001"},
        SameRule{"action = \"exception\"\nexception = \"busy\"\n",
                 R"({"action":"exception","exception":"busy"})",
                 "exception: expected an integer, got the string \"busy\""},
        SameRule{"action = \"garbage\"\ngarbage_bytes = 254\n",
                 R"({"action":"garbage","garbage_bytes":254})",
                 "garbage_bytes: expected an integer from 1 to 253, got 254"},
        SameRule{"action = \"drop\"\nfunctions = [3, 200]\n",
                 R"({"action":"drop","functions":[3,200]})",
                 "functions[1]: expected an integer from 1 to 127, got 200"},
        SameRule{"action = \"drop\"\nfunctions = [3, 3]\n",
                 R"({"action":"drop","functions":[3,3]})", "functions: the value 3 appears twice"},
        SameRule{"action = \"drop\"\nfunctions = 3\n", R"({"action":"drop","functions":3})",
                 "functions: expected an array, got 3"},
        SameRule{"action = \"drop\"\naddresses = [1, 2, 3]\n",
                 R"({"action":"drop","addresses":[1,2,3]})",
                 "addresses: expected two integers [first, last], got 3 elements"},
        SameRule{"action = \"drop\"\naddresses = [9, 2]\n",
                 R"({"action":"drop","addresses":[9,2]})",
                 "addresses: the first value 9 is greater than the last 2"},
        SameRule{"action = \"drop\"\naddresses = [0, 70000]\n",
                 R"({"action":"drop","addresses":[0,70000]})",
                 "addresses[1]: expected an integer from 0 to 65535, got 70000"},
        SameRule{"action = \"drop\"\nevery = 0\n", R"({"action":"drop","every":0})",
                 "every: expected an integer from 1 to 1000000, got 0"},
        SameRule{"action = \"drop\"\nprobability = 1.5\n", R"({"action":"drop","probability":1.5})",
                 "probability: expected a number from 0 to 1, got 1.5"},
        SameRule{"action = \"drop\"\nevery = 2\nprobability = 0.5\n",
                 R"({"action":"drop","every":2,"probability":0.5})",
                 "probability: give either every (every Nth request) or probability"},
        SameRule{"action = \"drop\"\ncolor = \"red\"\n", R"({"action":"drop","color":"red"})",
                 "color: unknown key; expected one of action, delay_ms, exception, garbage_bytes, "
                 "functions, addresses, every, probability"},
        SameRule{"action = \"delay\"\ndelay_ms = 250\nfunctions = [3, 16]\naddresses = [10, 20]\n"
                 "probability = 0.25\n",
                 R"({"action":"delay","delay_ms":250,"functions":[3,16],"addresses":[10,20],)"
                 R"("probability":0.25})",
                 ""},
        SameRule{"action = \"exception\"\nexception = 6\nevery = 3\n",
                 R"({"action":"exception","exception":6,"every":3})", ""}));

}  // namespace
}  // namespace mblab::test
