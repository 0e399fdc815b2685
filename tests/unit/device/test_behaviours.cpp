// Values that move ([[unit.behaviours]]): each kind on a manual clock, read back as a client reads
// them (FC 03 / 04 answers as hex), so the data type, byte order and scaling are checked too.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <thread>

#include "device_harness.hpp"
#include "support/manual_clock.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using device::BankKind;

// An hour after the Unix epoch began: what a timestamp behaviour reads as "now".
const auto kWall = std::chrono::system_clock::time_point{} + 1h;

class Behaviours : public ::testing::Test {
  protected:
    // One unit with holding 0..19 and input 0..19 mapped, plus `behaviours` (TOML tables).
    void load(const std::string& behaviours, const std::string& top = "") {
        clock = ManualClock{};
        device = device_from(top +
                             "[[unit]]\nid = 1\n"
                             "[[unit.holding_registers]]\nstart = 0\ncount = 20\n"
                             "[[unit.input_registers]]\nstart = 0\ncount = 20\n"
                             "[[unit.coils]]\nstart = 0\ncount = 4\n" +
                             behaviours);
    }
    // Moves the clock to `since_start` and lets the device catch up, as the server's timer does.
    void at(std::chrono::milliseconds since_start) {
        clock.advance_to(start + since_start);
        device->behaviours().advance(clock.now(), kWall + (clock.now() - start));
    }
    std::string ask(std::string_view request) { return test::ask(*device, request); }
    // `request`'s answer at each time of a trace, in order.
    void expect_trace(
        std::string_view request,
        std::initializer_list<std::pair<std::chrono::milliseconds, std::string_view>> trace) {
        for (const auto& [time, answer] : trace) {
            at(time);
            EXPECT_EQ(ask(request), answer) << "at " << time.count() << " ms";
        }
    }
    std::uint16_t input(std::uint16_t address) {
        return device->data().value(1, BankKind::InputRegisters, address).value_or(0xDEAD);
    }

    std::unique_ptr<device::ReferenceDevice> device;
    ManualClock clock;
    const ManualClock::time_point start = clock.now();
};

std::uint16_t sine_at(double seconds) {
    return static_cast<std::uint16_t>(
        std::lround(500 + 500 * std::sin(2 * std::numbers::pi * seconds / 10)));
}

TEST_F(Behaviours, SineReadBackMatchesTheFormulaAtChosenTimes) {
    load(
        "[[unit.behaviours]]\nkind = \"sine\"\nbank = \"input_registers\"\naddress = 3\n"
        "min = 0\nmax = 1000\nperiod_ms = 10000\ninterval_ms = 100\n");
    at(0ms);
    EXPECT_EQ(ask("04 00 03 00 01"), "04 02 01 F4");  // 500 at the start
    for (const int ms : {700, 1300}) {
        at(std::chrono::milliseconds(ms));
        EXPECT_EQ(input(3), sine_at(ms / 1000.0)) << "at " << ms << " ms";
    }
    at(2500ms);
    EXPECT_EQ(ask("04 00 03 00 01"), "04 02 03 E8");  // the crest, 1000, a quarter period in
    for (const int ms : {3300, 5000, 7500, 9900, 12300}) {
        at(std::chrono::milliseconds(ms));
        EXPECT_EQ(input(3), sine_at(ms / 1000.0)) << "at " << ms << " ms";
    }
    // Between updates the value is the last update's: 12.35 s reads as 12.3 s.
    at(12350ms);
    EXPECT_EQ(input(3), sine_at(12.3));
}

TEST_F(Behaviours, RampRisesAndWrapsToMin) {
    load(
        "[[unit.behaviours]]\nkind = \"ramp\"\naddress = 0\nmin = 10\nmax = 110\n"
        "period_ms = 1000\ninterval_ms = 100\n");
    const std::pair<int, std::uint16_t> expected[] = {{0, 10},    {500, 60},  {900, 100},
                                                      {1000, 10}, {1300, 40}, {2000, 10}};
    for (const auto& [ms, value] : expected) {
        at(std::chrono::milliseconds(ms));
        EXPECT_EQ(device->data().value(1, BankKind::HoldingRegisters, 0), value)
            << "at " << ms << " ms";
    }
}

std::vector<std::uint16_t> walk(std::uint64_t seed, std::chrono::milliseconds step_time) {
    auto device = device_from("behaviour_seed = " + std::to_string(seed) +
                              "\n[[unit]]\nid = 1\n[[unit.input_registers]]\nstart = 0\n"
                              "count = 2\n[[unit.behaviours]]\nkind = \"random-walk\"\n"
                              "bank = \"input_registers\"\naddress = 0\nmin = 100\nmax = 200\n"
                              "step = 5\ninterval_ms = 100\n");
    ManualClock clock;
    std::vector<std::uint16_t> values;
    for (int i = 0; i < 200; ++i) {
        device->behaviours().advance(clock.now(), kWall);
        values.push_back(*device->data().value(1, BankKind::InputRegisters, 0));
        clock.advance(step_time);
    }
    return values;
}

TEST_F(Behaviours, RandomWalkIsReproducibleForASeedAndStaysInBounds) {
    const auto first = walk(42, 100ms);
    EXPECT_EQ(walk(42, 100ms), first);
    EXPECT_NE(walk(43, 100ms), first);
    // The values depend on the update times, not on how often the device is advanced.
    const auto every_other = walk(42, 50ms);
    for (std::size_t i = 0; i < 100; ++i)
        EXPECT_EQ(every_other[2 * i], first[i]) << "update " << i;
    EXPECT_EQ(first.front(), 150);
    for (std::size_t i = 0; i < first.size(); ++i) {
        EXPECT_GE(first[i], 100);
        EXPECT_LE(first[i], 200);
        if (i) {
            EXPECT_LE(std::abs(first[i] - first[i - 1]), 6) << "update " << i;  // 5, rounded
        }
    }
}

TEST_F(Behaviours, RandomStaysInBoundsAndIsReproducible) {
    const std::string profile =
        "[[unit.behaviours]]\nkind = \"random\"\naddress = 0\ncount = 4\nmin = 1000\n"
        "max = 1010\ninterval_ms = 100\n";
    load(profile);
    std::vector<std::string> answers;
    for (int ms = 0; ms < 2000; ms += 100) {
        at(std::chrono::milliseconds(ms));
        for (std::uint16_t a = 0; a < 4; ++a) {
            const auto v = *device->data().value(1, BankKind::HoldingRegisters, a);
            EXPECT_GE(v, 1000);
            EXPECT_LE(v, 1010);
        }
        answers.push_back(ask("03 00 00 00 04"));
    }
    load(profile);
    for (int ms = 0; ms < 2000; ms += 100) {
        at(std::chrono::milliseconds(ms));
        EXPECT_EQ(ask("03 00 00 00 04"), answers[static_cast<std::size_t>(ms / 100)]);
    }
    EXPECT_NE(answers.front(), answers.back());
}

TEST_F(Behaviours, FollowerTakesTheSetpointAfterTheLag) {
    load(
        "[[unit.behaviours]]\nkind = \"follow\"\nbank = \"input_registers\"\naddress = 7\n"
        "source_bank = \"holding_registers\"\nsource = 2\nlag_ms = 2000\ninterval_ms = 100\n");
    at(0ms);
    at(900ms);
    EXPECT_EQ(ask("06 00 02 04 D2"), "06 00 02 04 D2");  // setpoint 1234 between updates
    at(1000ms);
    at(2900ms);
    EXPECT_EQ(ask("04 00 07 00 01"), "04 02 00 00");  // 2 s after 0.9 s: still the old value
    at(3000ms);
    EXPECT_EQ(ask("04 00 07 00 01"), "04 02 04 D2");
    EXPECT_EQ(ask("06 00 02 00 07"), "06 00 02 00 07");
    at(4000ms);
    EXPECT_EQ(input(7), 1234);
    at(6000ms);
    EXPECT_EQ(input(7), 7);
}

TEST_F(Behaviours, CounterStepsEachIntervalAndWrapsPastMax) {
    load(
        "[[unit.behaviours]]\nkind = \"counter\"\naddress = 0\nstart = 65534\n"
        "interval_ms = 500\n");
    expect_trace("03 00 00 00 01", {{0ms, "03 02 FF FE"},
                                    {700ms, "03 02 FF FF"},
                                    {1000ms, "03 02 00 00"},
                                    {2500ms, "03 02 00 03"}});
}

TEST_F(Behaviours, UptimeAndTimestampFollowTheClocksGiven) {
    load(
        "[[unit.behaviours]]\nkind = \"uptime\"\nbank = \"input_registers\"\naddress = 0\n"
        "type = \"u64\"\n"
        "[[unit.behaviours]]\nkind = \"timestamp\"\nbank = \"input_registers\"\naddress = 4\n"
        "type = \"u32\"\n");
    at(0ms);
    at(90'500ms);
    // 90 s of uptime (the update at 90 s), and 3600 + 90 s since the Unix epoch.
    EXPECT_EQ(ask("04 00 00 00 06"), "04 0C 00 00 00 00 00 00 00 5A 00 00 0E 6A");
}

struct Layout {
    std::string type;
    std::string order;
    std::string value;
    std::string hex;  // the registers as FC 03 answers them
};

class Layouts : public Behaviours, public ::testing::WithParamInterface<Layout> {};

TEST_P(Layouts, ConstantReadsBackInItsTypeAndOrder) {
    const auto& p = GetParam();
    load("[[unit.behaviours]]\nkind = \"constant\"\naddress = 4\ntype = \"" + p.type +
         "\"\norder = \"" + p.order + "\"\nvalue = " + p.value + "\n");
    at(0ms);
    const auto registers = static_cast<unsigned>((p.hex.size() + 1) / 6);
    EXPECT_EQ(ask("03 00 04 00 0" + std::to_string(registers)),
              "03 0" + std::to_string(2 * registers) + " " + p.hex);
}

INSTANTIATE_TEST_SUITE_P(
    WordAndByteOrders, Layouts,
    ::testing::Values(
        Layout{"u32", "ABCD", "305419896", "12 34 56 78"},  // 0x12345678
        Layout{"u32", "CDAB", "305419896", "56 78 12 34"},
        Layout{"u32", "BADC", "305419896", "34 12 78 56"},
        Layout{"u32", "DCBA", "305419896", "78 56 34 12"},
        Layout{"f32", "ABCD", "1.5", "3F C0 00 00"}, Layout{"f32", "CDAB", "1.5", "00 00 3F C0"},
        Layout{"f32", "BADC", "1.5", "C0 3F 00 00"}, Layout{"f32", "DCBA", "1.5", "00 00 C0 3F"},
        Layout{"i32", "ABCD", "-2", "FF FF FF FE"}, Layout{"i16", "ABCD", "-2", "FF FE"},
        Layout{"i16", "BADC", "-2", "FE FF"}, Layout{"u16", "ABCD", "70000", "FF FF"},  // saturates
        Layout{"u64", "CDAB", "4294967296", "00 00 00 00 00 01 00 00"},
        Layout{"i64", "ABCD", "-1", "FF FF FF FF FF FF FF FF"},
        Layout{"f64", "ABCD", "1.0", "3F F0 00 00 00 00 00 00"},
        Layout{"f64", "DCBA", "1.0", "00 00 00 00 00 00 F0 3F"}));

TEST_F(Behaviours, ScaleAndOffsetMapTheValueToTheRegister) {
    load(
        "[[unit.behaviours]]\nkind = \"constant\"\naddress = 0\nvalue = 21.5\nscale = 0.1\n"
        "[[unit.behaviours]]\nkind = \"constant\"\naddress = 1\ntype = \"i16\"\nvalue = -40\n"
        "scale = 0.5\noffset = -50\n");
    at(0ms);
    EXPECT_EQ(ask("03 00 00 00 02"), "03 04 00 D7 00 14");  // 215 and (-40 + 50) / 0.5 = 20
    const device::NumberLayout layout{device::NumberType::I16, {}, 0.5, -50};
    const std::uint16_t raw = 20;
    EXPECT_EQ(device::decode_number(std::span(&raw, 1), layout), -40);
}

TEST_F(Behaviours, CoilsTakeTheValueRounded) {
    load(
        "[[unit.behaviours]]\nkind = \"ramp\"\nbank = \"coils\"\naddress = 1\nmin = -0.5\n"
        "max = 1.5\nperiod_ms = 10000\ninterval_ms = 100\n");
    expect_trace(
        "01 00 01 00 01",
        {{0ms, "01 01 00"}, {4900ms, "01 01 00"}, {5100ms, "01 01 01"}, {10000ms, "01 01 00"}});
}

TEST_F(Behaviours, DeadlineIsTheNextUpdate) {
    load(
        "[[unit.behaviours]]\nkind = \"counter\"\naddress = 0\ninterval_ms = 500\n"
        "[[unit.behaviours]]\nkind = \"counter\"\naddress = 1\ninterval_ms = 300\n");
    EXPECT_EQ(device->behaviours().deadline(), ManualClock::time_point::min());
    at(0ms);
    EXPECT_EQ(device->behaviours().deadline(), start + 300ms);
    at(300ms);
    EXPECT_EQ(device->behaviours().deadline(), start + 500ms);
    load("");
    EXPECT_EQ(device->behaviours().deadline(), ManualClock::time_point::max());
}

// A request between two updates of a multi-register value sees all of one update: the counter
// steps by 0x00010001, so both words are equal in every whole value, and a read that saw half
// an update would find them different. Requests run on this thread while another advances.
TEST_F(Behaviours, MultiRegisterValueIsNeverHalfUpdated) {
    load(
        "[[unit.behaviours]]\nkind = \"counter\"\nbank = \"input_registers\"\naddress = 0\n"
        "type = \"u32\"\nstep = 65537\ninterval_ms = 10\n");
    at(0ms);
    std::atomic<bool> done = false;
    std::thread updates([&] {
        for (int i = 1; i <= 20000; ++i)
            device->behaviours().advance(start + i * 10ms, kWall);
        done = true;
    });
    int reads = 0;
    std::string torn;
    while ((!done || reads < 100) && torn.empty()) {
        const auto answer = ask("04 00 00 00 02");
        if (answer.size() != 17 || answer.substr(6, 5) != answer.substr(12, 5)) torn = answer;
        ++reads;
    }
    updates.join();
    EXPECT_EQ(torn, "") << "after " << reads << " reads";
    EXPECT_EQ(ask("04 00 00 00 02"), "04 04 4E 20 4E 20");  // 20000 steps
}

TEST_F(Behaviours, ShippedMovingProfileMoves) {
    device = shipped_device("moving");
    at(0ms);
    const auto first = ask("04 00 00 00 01");
    EXPECT_EQ(first, "04 02 01 F4");
    at(1000ms);
    EXPECT_NE(ask("04 00 00 00 01"), first);
    // Inputs 16-19: the f64 3.14159 (0x400921F9F01B866E) in DCBA order.
    EXPECT_EQ(ask("04 00 10 00 04"), "04 08 6E 86 1B F0 F9 21 09 40");
}

// The example table in docs/profiles.md loads as printed, in a unit that maps its registers.
TEST_F(Behaviours, TheDocumentedExampleLoads) {
    std::ifstream in(std::string(MBLAB_SOURCE_DIR) + "/docs/profiles.md");
    std::string line;
    std::string example;
    bool section = false;
    bool inside = false;
    while (std::getline(in, line)) {
        if (line.starts_with("### `[[unit.behaviours]]`")) section = true;
        if (section && inside && line == "```") break;
        if (inside) example += line + "\n";
        if (section && line == "```toml") inside = true;
    }
    ASSERT_NE(example.find("kind = \"sine\""), std::string::npos) << example;
    load(example);
    at(0ms);
    // f32 0.0 (the sine's middle) at 0; scale 0.1 makes a crest of 50 the f32 500.
    EXPECT_EQ(ask("04 00 00 00 02"), "04 04 00 00 00 00");
    at(2500ms);
    EXPECT_EQ(ask("04 00 00 00 02"), "04 04 00 00 43 FA");
}

struct BadBehaviour {
    std::string_view table;
    std::string_view error;
};

class BehaviourErrors : public ::testing::TestWithParam<BadBehaviour> {};

TEST_P(BehaviourErrors, NameFileLineKeyAndFix) {
    const std::string text = std::string(
                                 "[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\n"
                                 "count = 10\n[[unit.behaviours]]\n") +
                             std::string(GetParam().table);
    EXPECT_EQ(profile_error(text), GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BehaviourErrors,
    ::testing::Values(
        BadBehaviour{"kind = \"wave\"\naddress = 0\n",
                     "test.toml:7: unit[0].behaviours[0].kind: expected one of constant, ramp, "
                     "sine, random-walk, random, counter, uptime, timestamp, follow, got \"wave\""},
        BadBehaviour{"kind = \"sine\"\naddress = 0\nmin = 5\nmax = 5\nperiod_ms = 1000\n",
                     "test.toml:10: unit[0].behaviours[0].max: expected a number above min (5)"},
        BadBehaviour{"kind = \"sine\"\naddress = 0\nmin = 0\nmax = 5\n",
                     "test.toml:6: unit[0].behaviours[0].period_ms: missing key; the time of "
                     "one cycle, e.g. period_ms = 60000"},
        BadBehaviour{"kind = \"uptime\"\naddress = 9\ntype = \"u32\"\n",
                     "test.toml:8: unit[0].behaviours[0].address: holding_registers 9..10 are "
                     "not all in the unit's ranges; add a range for them"},
        BadBehaviour{"kind = \"uptime\"\naddress = 0\nbank = \"input_registers\"\n",
                     "test.toml:8: unit[0].behaviours[0].address: input_registers 0..0 are not "
                     "all in the unit's ranges; add a range for them"},
        BadBehaviour{"kind = \"uptime\"\naddress = 0\ntype = \"u64\"\n[[unit.behaviours]]\n"
                     "kind = \"counter\"\naddress = 3\n",
                     "test.toml:12: unit[0].behaviours[1].address: 3..3 overlap behaviours[0] "
                     "(0..3); one behaviour drives a register"},
        BadBehaviour{"kind = \"constant\"\naddress = 0\nvalue = 1\nscale = 0\n",
                     "test.toml:10: unit[0].behaviours[0].scale: expected a number other than 0 "
                     "(the register holds value / scale)"},
        BadBehaviour{"kind = \"constant\"\naddress = 0\nvalue = 1\norder = \"ABDC\"\n",
                     "test.toml:10: unit[0].behaviours[0].order: expected one of ABCD, CDAB, "
                     "BADC, DCBA, got \"ABDC\""},
        BadBehaviour{"kind = \"uptime\"\naddress = 0\nmin = 1\n",
                     "test.toml:9: unit[0].behaviours[0].min: unknown key; expected one of kind, "
                     "interval_ms, bank, address, count, type, order, scale, offset"},
        BadBehaviour{"kind = \"follow\"\naddress = 0\nsource = 5\nsource_bank = \"coils\"\n",
                     "test.toml:10: unit[0].behaviours[0].source_bank: a follower copies "
                     "registers from registers and bits from bits"},
        BadBehaviour{"kind = \"counter\"\naddress = 0\ninterval_ms = 5\n",
                     "test.toml:9: unit[0].behaviours[0].interval_ms: expected an integer from "
                     "10 to 86400000, got 5"}));

}  // namespace
}  // namespace mblab::test
