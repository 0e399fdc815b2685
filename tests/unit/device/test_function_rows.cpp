// The address scope column of the function table, seen through a fault rule with an address
// filter: a request is caught exactly when the addresses its row says it names overlap the filter.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>

#include "device_harness.hpp"
#include "protocol/function_table.hpp"

namespace mblab::test {
namespace {

constexpr std::string_view kProfile = R"(
fault_seed = 1
[[unit]]
id = 1
holding_registers = [{start = 0, count = 300}]
faults = [{action = "drop", addresses = [100, 199]}]
)";

struct Probe {
    std::uint8_t code;
    const char* inside;   // names an address in 100..199
    const char* outside;  // names none
};

// Address 0x96 = 150 is inside, 0x0A = 10 outside.
constexpr Probe kProbes[] = {
    {0x01, "01 00 96 00 01", "01 00 0A 00 01"},
    {0x02, "02 00 96 00 01", "02 00 0A 00 01"},
    {0x03, "03 00 5F 00 0A", "03 00 0A 00 0A"},  // 95..104 overlaps
    {0x04, "04 00 96 00 01", "04 00 0A 00 01"},
    {0x05, "05 00 96 FF 00", "05 00 0A FF 00"},
    {0x06, "06 00 96 00 01", "06 00 0A 00 01"},
    {0x0F, "0F 00 60 00 0A 02 FF 03", "0F 00 0A 00 0A 02 FF 03"},  // 96..105 overlaps
    {0x10, "10 00 96 00 01 02 00 01", "10 00 0A 00 01 02 00 01"},
    {0x16, "16 00 96 FF FF 00 00", "16 00 0A FF FF 00 00"},
    // FC 17 names everything from the lower start to the higher end: reading 0, writing 200.
    {0x17, "17 00 00 00 01 00 C8 00 01 02 00 01", "17 00 00 00 01 00 0A 00 01 02 00 01"},
    {0x18, "18 00 96", "18 00 0A"},
};

TEST(FunctionRows, AddressFilterSeesTheScopeOfEveryRow) {
    auto device = device_from(kProfile);
    for (const Probe& probe : kProbes) {
        const auto* row = protocol::find_function(probe.code);
        ASSERT_NE(row, nullptr);
        EXPECT_NE(row->scope, protocol::AddressScope::None) << row->name;
        EXPECT_EQ(ask(*device, probe.inside), "NO ANSWER") << probe.inside;
        EXPECT_NE(ask(*device, probe.outside), "NO ANSWER") << probe.outside;
    }
}

TEST(FunctionRows, RowsWithoutAScopeAreNeverFiltered) {
    auto device = device_from(kProfile);
    for (const protocol::FunctionRow& row : protocol::kFunctionTable) {
        const auto code = static_cast<std::uint8_t>(row.code);
        const bool probed = std::any_of(std::begin(kProbes), std::end(kProbes),
                                        [&](const Probe& probe) { return probe.code == code; });
        EXPECT_EQ(probed, row.scope != protocol::AddressScope::None) << row.name;
    }
    for (const char* request : {"07", "08 00 0B 00 00", "0B", "0C", "11", "2B 0E 01 00",
                                "14 07 06 00 01 00 96 00 01", "5B 09 00 00 01 00 01 00 07 00 01"})
        EXPECT_NE(ask(*device, request), "NO ANSWER") << request;
}

}  // namespace
}  // namespace mblab::test
