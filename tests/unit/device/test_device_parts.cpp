// The parts of the reference device, each over a DeviceUnits of its own without the Modbus
// face: data tables, line counters, fault rules, declarations, and the one lock they share.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>

#include "device/device_units.hpp"
#include "device/fault_rule_table.hpp"
#include "device/line_counters.hpp"
#include "device/profile_loader.hpp"
#include "device/unit_data.hpp"
#include "device/unit_declarations.hpp"

namespace mblab::test {
namespace {

using device::BankKind;

// Unit 1: holding registers 0..9 and 20..29 (a hole between); unit 7: coils 0..15.
constexpr std::string_view kProfile = R"(
[[unit]]
id = 1
max_read_registers = 40
[[unit.holding_registers]]
start = 0
count = 10
[[unit.holding_registers]]
start = 20
count = 10

[[unit]]
id = 7
[[unit.coils]]
start = 0
count = 16
)";

device::DeviceUnits make_units() {
    auto profile = device::parse_profile(kProfile, "parts.toml");
    EXPECT_TRUE(profile) << profile.error();
    return device::DeviceUnits(std::move(profile).value());
}

TEST(UnitData, ReadsHolesAsNothingAndRefusesAWriteOverOneWhole) {
    auto units = make_units();
    device::UnitData data(units);
    const std::array<std::uint16_t, 3> three{1, 2, 3};
    EXPECT_TRUE(data.set_values(1, BankKind::HoldingRegisters, 7, three));
    const auto read = data.values(1, BankKind::HoldingRegisters, 8, 4);
    ASSERT_TRUE(read);
    EXPECT_EQ(*read, (std::vector<std::optional<std::uint16_t>>{2, 3, std::nullopt, std::nullopt}));
    // 9 is mapped, 10 is not: nothing is written.
    EXPECT_FALSE(data.set_values(1, BankKind::HoldingRegisters, 9, three));
    EXPECT_EQ(data.value(1, BankKind::HoldingRegisters, 9), 3);
    EXPECT_FALSE(data.set_value(1, BankKind::HoldingRegisters, 15, 1));
    EXPECT_EQ(data.value(1, BankKind::HoldingRegisters, 15), std::nullopt);
    EXPECT_FALSE(data.values(2, BankKind::HoldingRegisters, 0, 1));
    EXPECT_TRUE(data.set_value(7, BankKind::Coils, 3, 1));
    EXPECT_EQ(data.value(7, BankKind::Coils, 3), 1);
}

TEST(LineCounters, LineEventsCountOnEveryUnitABusyReplyOnOne) {
    auto units = make_units();
    device::LineCounters counters(units);
    counters.count_crc_error();
    counters.count_parity_error();
    counters.count_short_frame();
    counters.count_overrun();
    counters.count_busy_reply(7);
    for (std::uint8_t unit : {1, 7}) {
        const auto stats = counters.stats(unit);
        ASSERT_TRUE(stats);
        EXPECT_EQ(stats->counters.bus_errors, 3);
        EXPECT_EQ(stats->counters.overruns, 1);
    }
    EXPECT_EQ(counters.stats(1)->counters.busy, 0);
    EXPECT_EQ(counters.stats(7)->counters.busy, 1);
    EXPECT_EQ(counters.stats(7)->counters.bus_exceptions, 1);
    EXPECT_FALSE(counters.stats(2));
    EXPECT_EQ(counters.ascii_delimiter(1), '\n');
    EXPECT_EQ(counters.ascii_delimiter(2), '\n');
}

TEST(LineCounters, ClearingKeepsTheLog) {
    auto units = make_units();
    device::LineCounters counters(units);
    counters.count_crc_error();
    units.locked([](device::UnitTable& table) {
        table.find(1)->comm().log.add(device::event::kReceive);
        table.find(1)->comm().event_count = 4;
    });
    EXPECT_TRUE(counters.clear_counters(1));
    EXPECT_EQ(counters.stats(1)->counters.bus_errors, 0);
    EXPECT_EQ(counters.stats(1)->event_count, 0);
    EXPECT_EQ(counters.event_log(1), (std::vector<std::uint8_t>{device::event::kReceive}));
    // Unit 7 keeps its counts.
    EXPECT_EQ(counters.stats(7)->counters.bus_errors, 1);
    EXPECT_FALSE(counters.clear_counters(2));
    EXPECT_FALSE(counters.event_log(2));
}

TEST(FaultRuleTable, ReplacesOneUnitsRules) {
    auto units = make_units();
    device::FaultRuleTable faults(units);
    EXPECT_EQ(faults.rules(1)->size(), 0U);
    device::FaultSpec busy;
    busy.action = device::FaultAction::Exception;
    busy.every = 3;
    EXPECT_TRUE(faults.set_rules(1, {busy, busy}));
    EXPECT_EQ(faults.rules(1)->size(), 2U);
    EXPECT_EQ(faults.rules(1)->front().every, 3U);
    EXPECT_EQ(faults.rules(7)->size(), 0U);
    EXPECT_FALSE(faults.set_rules(2, {busy}));
    EXPECT_FALSE(faults.rules(2));
}

TEST(UnitDeclarations, TellEachUnitsLimitsAndMap) {
    const auto units = make_units();
    const device::UnitDeclarations declarations(units);
    EXPECT_EQ(declarations.unit_ids(), (std::vector<std::uint8_t>{1, 7}));
    EXPECT_EQ(declarations.profile().units.size(), 2U);
    const auto first = declarations.first();
    EXPECT_EQ(first.unit, 1);
    EXPECT_EQ(first.max_read_registers, 40);
    EXPECT_EQ(first.holding_registers, 10U);  // 0..9, then a hole
    EXPECT_EQ(declarations.of(7)->holding_registers, 0U);
    EXPECT_FALSE(declarations.of(2));
    EXPECT_EQ(declarations.addressing(device::Link::Serial),
              "addresses 1,7 (0 is a broadcast; other addresses are not answered)");
}

// The one lock: a reader never sees a range half-written by another part's call.
TEST(DeviceUnits, OneLockKeepsEachCallWhole) {
    auto units = make_units();
    device::UnitData writer(units);
    device::UnitData reader(units);
    std::atomic<bool> done{false};
    std::thread writes([&] {
        std::array<std::uint16_t, 10> range{};
        for (std::uint16_t round = 1; round <= 2000; ++round) {
            range.fill(round);
            writer.set_values(1, BankKind::HoldingRegisters, 0, range);
        }
        done = true;
    });
    int torn = 0;
    while (!done) {
        const auto read = reader.values(1, BankKind::HoldingRegisters, 0, 10);
        for (const auto& value : *read)
            torn += value != read->front() ? 1 : 0;
    }
    writes.join();
    EXPECT_EQ(torn, 0);
    EXPECT_EQ(reader.value(1, BankKind::HoldingRegisters, 9), 2000);
}

}  // namespace
}  // namespace mblab::test
