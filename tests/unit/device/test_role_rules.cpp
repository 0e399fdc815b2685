// Modbus/TCP Security authorization: which role may send which request, from [[role]] tables.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "device/profile_loader.hpp"
#include "device/role_rules.hpp"
#include "device_harness.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

using device::RoleRules;

RoleRules rules_from(std::string_view roles) {
    auto loaded = device::parse_profile(std::string(roles) + "\n[[unit]]\nid = 1\n", "test.toml");
    EXPECT_TRUE(loaded) << (loaded ? "" : loaded.error());
    return loaded ? RoleRules(loaded.value().roles) : RoleRules();
}

bool permits(const RoleRules& rules, std::optional<std::string> role, std::string_view pdu,
             std::uint8_t unit = 1) {
    const auto bytes = hex(pdu);
    return rules.permits(role, unit, bytes);
}

constexpr std::string_view kShipped = R"(
[[role]]
name = "ReadOnly"
functions = [1, 2, 3, 4, 20, 24]
[[role]]
name = "Operator"
functions = [1, 2, 3, 4, 5, 6, 15, 16, 20, 21, 22, 23, 24]
[[role]]
name = "Administrator"
)";

TEST(RoleRules, ReadOnlyReadsButDoesNotWrite) {
    const auto rules = rules_from(kShipped);
    EXPECT_TRUE(permits(rules, "ReadOnly", "03 00 00 00 0A"));
    EXPECT_FALSE(permits(rules, "ReadOnly", "06 00 0A 00 07"));
    EXPECT_FALSE(permits(rules, "ReadOnly", "08 00 00 12 34"));
    EXPECT_FALSE(permits(rules, "ReadOnly", "2B 0E 01 00"));
}

TEST(RoleRules, OperatorWritesDataButRunsNoDiagnostics) {
    const auto rules = rules_from(kShipped);
    EXPECT_TRUE(permits(rules, "Operator", "10 00 00 00 01 02 12 34"));
    EXPECT_FALSE(permits(rules, "Operator", "08 00 01 00 00"));
    EXPECT_FALSE(permits(rules, "Operator", "2B 0E 01 00"));
}

TEST(RoleRules, AdministratorMayDoEverythingUserDefinedCodesIncluded) {
    const auto rules = rules_from(kShipped);
    for (auto pdu : {"08 00 01 00 00", "2B 0E 01 00", "41 01 02", "06 FF FF 00 01"})
        EXPECT_TRUE(permits(rules, "Administrator", pdu)) << pdu;
}

TEST(RoleRules, NoRoleAndUnknownRolesMayDoNothing) {
    const auto rules = rules_from(kShipped);
    EXPECT_FALSE(permits(rules, std::nullopt, "03 00 00 00 01"));
    EXPECT_FALSE(permits(rules, "readonly", "03 00 00 00 01"));  // roles match exactly
    EXPECT_FALSE(permits(rules, "Guest", "03 00 00 00 01"));
    EXPECT_FALSE(RoleRules().permits(std::string("Administrator"), 1, hex("03 00 00 00 01")));
}

TEST(RoleRules, AccessFollowsTheFunctionTablesWritesColumn) {
    const auto rules = rules_from(
        "[[role]]\nname = \"Reader\"\naccess = \"read\"\n"
        "[[role]]\nname = \"Writer\"\naccess = \"write\"\n");
    EXPECT_TRUE(permits(rules, "Reader", "04 00 00 00 01"));
    EXPECT_TRUE(permits(rules, "Reader", "08 00 00 12 34"));
    EXPECT_FALSE(permits(rules, "Reader", "05 00 00 FF 00"));
    EXPECT_FALSE(permits(rules, "Reader", "41 00"));  // a code outside the table may write
    EXPECT_TRUE(permits(rules, "Writer", "05 00 00 FF 00"));
    EXPECT_TRUE(permits(rules, "Writer", "17 00 00 00 01 00 00 00 01 02 00 00"));
    EXPECT_FALSE(permits(rules, "Writer", "03 00 00 00 01"));
}

TEST(RoleRules, AddressRangeHoldsForEveryAddressARequestNames) {
    const auto rules = rules_from("[[role]]\nname = \"Tuner\"\naddresses = [100, 199]\n");
    EXPECT_TRUE(permits(rules, "Tuner", "03 00 64 00 64"));   // 100..199
    EXPECT_FALSE(permits(rules, "Tuner", "03 00 64 00 65"));  // 100..200
    EXPECT_FALSE(permits(rules, "Tuner", "06 00 63 00 01"));  // 99
    EXPECT_TRUE(permits(rules, "Tuner", "06 00 C7 00 01"));   // 199
    // FC 23 names both its ranges.
    EXPECT_FALSE(permits(rules, "Tuner", "17 00 64 00 01 00 00 00 01 02 00 00"));
    EXPECT_TRUE(permits(rules, "Tuner", "08 00 00 12 34"));  // names no address
    EXPECT_FALSE(permits(rules, "Tuner", "03 00 64"));       // its addresses cannot be read
    EXPECT_FALSE(permits(rules, "Tuner", "41 00 64"));       // nor those of an unlisted code
}

TEST(RoleRules, UnitsLimitARule) {
    const auto rules = rules_from("[[role]]\nname = \"Field\"\nunits = [2, 3]\n");
    EXPECT_TRUE(permits(rules, "Field", "03 00 00 00 01", 2));
    EXPECT_FALSE(permits(rules, "Field", "03 00 00 00 01", 1));
}

TEST(RoleRules, RulesOfOneRoleAddUp) {
    const auto rules = rules_from(
        "[[role]]\nname = \"Mixed\"\nfunctions = [3]\n"
        "[[role]]\nname = \"Mixed\"\nfunctions = [6]\naddresses = [10, 10]\n");
    EXPECT_TRUE(permits(rules, "Mixed", "03 00 00 00 01"));
    EXPECT_TRUE(permits(rules, "Mixed", "06 00 0A 00 01"));
    EXPECT_FALSE(permits(rules, "Mixed", "06 00 0B 00 01"));
}

TEST(RoleRules, BadRoleTablesAreOneLineErrors) {
    EXPECT_EQ(profile_error("[[role]]\nfunctions = [3]\n[[unit]]\nid = 1\n"),
              "test.toml:1: role[0].name: missing key; the role as certificates carry it, e.g. "
              "name = \"Operator\"");
    EXPECT_EQ(profile_error("[[role]]\nname = \"\"\n[[unit]]\nid = 1\n"),
              "test.toml:2: role[0].name: a role name cannot be empty");
    EXPECT_EQ(profile_error("[[role]]\nname = \"X\"\naccess = \"rw\"\n[[unit]]\nid = 1\n"),
              "test.toml:3: role[0].access: expected one of any, read, write, got \"rw\"");
    EXPECT_EQ(profile_error("[[role]]\nname = \"X\"\nfunction = [3]\n[[unit]]\nid = 1\n"),
              "test.toml:3: role[0].function: unknown key; expected one of name, functions, "
              "access, units, addresses");
}

}  // namespace
}  // namespace mblab::test
