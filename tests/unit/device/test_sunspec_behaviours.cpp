// Behaviours on SunSpec points by name ([[unit.sunspec.model.behaviours]]): the value in
// engineering units, the register value / 10^sf of the scale factor as it is when the update is
// computed; accumulators only increase; a point named wrong is one line naming it and its model.
// Model 103 at 70 (base 0): W 84, W_SF 85, Hz 86, Hz_SF 87, WH 94-95, WH_SF 96, TmpSnk 104,
// Tmp_SF 107; model 122 at 122: ActWh 127-130 (acc64), Tms 163-164 (uint32), neither scaled.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "device_harness.hpp"
#include "support/manual_clock.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

std::string chain(std::string_view knobs, std::string_view inverter, std::string_view status) {
    return std::string("[[unit]]\nid = 1\n[unit.sunspec]\nbase = 0\n") + std::string(knobs) +
           "\n[[unit.sunspec.model]]\nid = 1\npoints = { Mn = \"m\", Md = \"d\", SN = \"1\" }\n"
           "[[unit.sunspec.model]]\nid = 103\n"
           "points = { W_SF = 1, Hz_SF = -2, WH_SF = 1, Tmp_SF = -1 }\n" +
           std::string(inverter) + "\n[[unit.sunspec.model]]\nid = 122\n" + std::string(status);
}

class SunSpecBehaviours : public ::testing::Test {
  protected:
    void load(std::string_view inverter, std::string_view status = "",
              std::string_view knobs = "") {
        device = device_from(chain(knobs, inverter, status));
    }
    void at(std::chrono::milliseconds since_start) {
        clock.advance_to(start + since_start);
        device->behaviours().advance(clock.now(), std::chrono::system_clock::time_point{});
    }
    std::string ask(std::string_view request) { return test::ask(*device, request); }
    // `request`'s answer at each time, in order.
    void expect_trace(std::string_view request,
                      std::vector<std::pair<std::chrono::milliseconds, std::string>> trace) {
        for (const auto& step : trace) {
            at(step.first);
            EXPECT_EQ(ask(request), step.second) << "at " << step.first.count() << " ms";
        }
    }

    std::unique_ptr<device::ReferenceDevice> device;
    ManualClock clock;
    const ManualClock::time_point start = clock.now();
};

// W moving 0..5000 W with W_SF = 1 holds 0..500: the ramp's 2500 W at 5 s is 250.
TEST_F(SunSpecBehaviours, RampOnWInWattsIsStoredInTensOfWatts) {
    load(
        R"(behaviours = [{ point = "W", kind = "ramp", min = 0, max = 5000, period_ms = 10000 }])");
    // Before the first update W holds where the ramp starts, not "not implemented".
    EXPECT_EQ(ask("03 00 54 00 02"), "03 04 00 00 00 01");
    expect_trace("03 00 54 00 01",
                 {{0ms, "03 02 00 00"}, {5000ms, "03 02 00 FA"}, {9000ms, "03 02 01 C2"}});
}

// A negative scale factor multiplies: -12.3 C with Tmp_SF = -1 is int16 -123; 50.02 Hz (uint16)
// with Hz_SF = -2 is 5002.
TEST_F(SunSpecBehaviours, NegativeScaleFactorsOnSignedAndUnsignedPoints) {
    load(
        R"(behaviours = [{ point = "TmpSnk", kind = "constant", value = -12.3 }, { point = "Hz", kind = "constant", value = 50.02 }])");
    at(0ms);
    EXPECT_EQ(ask("03 00 68 00 01"), "03 02 FF 85");
    EXPECT_EQ(ask("03 00 56 00 01"), "03 02 13 8A");
}

// WH (acc32, WH_SF = 1): 1000000 Wh is 100000 in two registers, high word first, both written
// in one update; past a max of its own an accumulator stays there instead of wrapping.
TEST_F(SunSpecBehaviours, AccumulatorCountsUpAndStopsAtItsOwnMax) {
    load(
        R"(behaviours = [{ point = "WH", kind = "counter", start = 1000000, max = 1000020, step = 10 }])");
    expect_trace(
        "03 00 5E 00 02",
        {{0ms, "03 04 00 01 86 A0"}, {1000ms, "03 04 00 01 86 A1"}, {5000ms, "03 04 00 01 86 A2"}});
}

// Without a max of its own, WH (acc32) rolls over at the type's end to its lowest value, 1 (0 is
// "not implemented"), as a meter's register does.
TEST_F(SunSpecBehaviours, AccumulatorRollsOverAtItsTypesEnd) {
    load(R"(behaviours = [{ point = "WH", kind = "counter", start = 42949672940, step = 10 }])");
    expect_trace(
        "03 00 5E 00 02",
        {{0ms, "03 04 FF FF FF FE"}, {1000ms, "03 04 FF FF FF FF"}, {2000ms, "03 04 00 00 00 01"}});
}

// An accumulator's counter starts above 0 by default: 0 is its "not implemented" value.
TEST_F(SunSpecBehaviours, AccumulatorCounterDefaultsAvoidNotImplemented) {
    load("", R"(behaviours = [{ point = "ActWh", kind = "counter" }])");
    at(0ms);
    EXPECT_EQ(ask("03 00 7F 00 04"), "03 08 00 00 00 00 00 00 00 01");
}

// Points no scale factor scales take the value as it is: Tms (uint32) 70000 s.
TEST_F(SunSpecBehaviours, PointWithoutScaleFactorTakesTheValueAsItIs) {
    load("", R"(behaviours = [{ point = "Tms", kind = "constant", value = 70000 }])");
    at(0ms);
    EXPECT_EQ(ask("03 00 A3 00 02"), "03 04 00 01 11 70");
}

// The scale factor is read when each update is computed: W_SF written 2 (here an R point that
// takes writes, a knob) makes the next update of 5000 W store 50.
TEST_F(SunSpecBehaviours, ScaleFactorIsReadAtEachUpdate) {
    load(R"(behaviours = [{ point = "W", kind = "constant", value = 5000 }])", "",
         "read_only_writable = true");
    at(0ms);
    EXPECT_EQ(ask("03 00 54 00 01"), "03 02 01 F4");
    EXPECT_EQ(ask("06 00 55 00 02"), "06 00 55 00 02");
    at(1000ms);
    EXPECT_EQ(ask("03 00 54 00 02"), "03 04 00 32 00 02");
}

TEST_F(SunSpecBehaviours, ShippedInverterMovesItsPowerAndEnergy) {
    device = shipped_device("sunspec-inverter");
    // Before the first update too, as on a device whose behaviours do not run.
    EXPECT_EQ(ask("03 9C 94 00 01"), "03 02 02 26");
    at(0ms);
    // 103 W at 40084 (0x9C94): the sine's middle 5500 W is 550; WH at 40094 1000000 Wh.
    EXPECT_EQ(ask("03 9C 94 00 02"), "03 04 02 26 00 01");
    EXPECT_EQ(ask("03 9C 9E 00 02"), "03 04 00 01 86 A0");
    at(15000ms);
    // A quarter period later the crest 9000 W; three counts of 10 Wh.
    EXPECT_EQ(ask("03 9C 94 00 01"), "03 02 03 84");
    EXPECT_EQ(ask("03 9C 9E 00 02"), "03 04 00 01 86 A3");
}

// The example in docs/sunspec.md "Values that move" loads as printed after a common model 1.
TEST_F(SunSpecBehaviours, TheDocumentedExampleLoads) {
    std::ifstream in(std::string(MBLAB_SOURCE_DIR) + "/docs/sunspec.md");
    const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto from = doc.find("```toml\n", doc.find("### Values that move")) + 8;
    ASSERT_LT(from, doc.size());
    device = device_from(
        "[[unit]]\nid = 1\n[unit.sunspec]\nbase = 0\n[[unit.sunspec.model]]\n"
        "id = 1\npoints = { Mn = \"m\", Md = \"d\", SN = \"1\" }\n" +
        doc.substr(from, doc.find("```", from) - from));
    // W half way up its ramp at 30 s: 2500 W as 250; WH 1000000 Wh as 100000, 10 Wh more.
    at(0ms);
    at(30000ms);
    EXPECT_EQ(ask("03 00 54 00 01"), "03 02 00 FA");
    EXPECT_EQ(ask("03 00 5E 00 02"), "03 04 00 01 86 A6");
}

// Each table (of model 103) and the error it gets.
const std::pair<std::string_view, std::string_view> kBadPoints[] = {
    {"[[unit.sunspec.model.behaviours]]\npoint = \"Watts\"\nkind = \"sine\"\n",
     "test.toml:13: unit[0].sunspec.model[1].behaviours[0].point: model 103: no "
     "point \"Watts\" to drive"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"WH\"\nkind = \"sine\"\nmin = 1\n"
     "max = 2\nperiod_ms = 1000\n",
     "test.toml:14: unit[0].sunspec.model[1].behaviours[0].kind: model 103: WH is "
     "an accumulator (acc32), which only increases; use counter or constant"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"WH\"\nkind = \"counter\"\n"
     "step = -1\n",
     "test.toml:15: unit[0].sunspec.model[1].behaviours[0].step: model 103: WH is "
     "an accumulator (acc32), which only increases; give a step above 0"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"VA\"\nkind = \"constant\"\n"
     "value = 1\n",
     "test.toml:13: unit[0].sunspec.model[1].behaviours[0].point: model 103: VA is "
     "scaled by VA_SF, which has no value; give VA_SF one in points"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"W_SF\"\nkind = \"constant\"\n"
     "value = 1\n",
     "test.toml:13: unit[0].sunspec.model[1].behaviours[0].point: model 103: W_SF "
     "is sunssf; a behaviour drives int, uint, acc and float points"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"W\"\nkind = \"sine\"\nmin = 0\n"
     "max = 400000\nperiod_ms = 1000\n",
     "test.toml:16: unit[0].sunspec.model[1].behaviours[0].max: model 103: W (int16, "
     "scale 10) holds -327670..327670; 0..400000 does not fit"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"W\"\nkind = \"uptime\"\n",
     "test.toml:14: unit[0].sunspec.model[1].behaviours[0].kind: model 103: W: a "
     "SunSpec point takes constant, ramp, sine, random-walk, random or counter"},
    {"[[unit.sunspec.model.behaviours]]\npoint = \"W\"\nkind = \"constant\"\n"
     "value = 1\naddress = 3\n",
     "test.toml:16: unit[0].sunspec.model[1].behaviours[0].address: unknown key; "
     "expected one of point, kind, interval_ms, value"}};

TEST(SunSpecBehaviourErrors, OneLineNamingTheModelAndPoint) {
    for (const auto& [table, error] : kBadPoints)
        EXPECT_EQ(profile_error(chain("", table, "")), error);
}

// A point given a value and a behaviour, or two behaviours, is refused; so is a behaviour by
// address on a register a SunSpec point's behaviour drives.
TEST(SunSpecBehaviourConflicts, OneSourceForEachPoint) {
    const std::string behaviour =
        "[[unit.sunspec.model.behaviours]]\npoint = \"W\"\n"
        "kind = \"constant\"\nvalue = 5000\n";
    auto valued = chain("", behaviour, "");
    valued.replace(valued.find("W_SF = 1"), 8, "W_SF = 1, W = 3");
    EXPECT_NE(profile_error(valued).find("model 103: W has a value in points too; give it one "
                                         "or the other"),
              std::string::npos)
        << profile_error(valued);
    EXPECT_NE(profile_error(chain("", behaviour + behaviour, ""))
                  .find("model 103: W has a behaviour already; one behaviour drives a point"),
              std::string::npos);
    const auto by_address =
        profile_error(chain("", behaviour, "") +
                      "[[unit.behaviours]]\nkind = \"constant\"\naddress = 84\nvalue = 1\n");
    EXPECT_NE(by_address.find("84..84 overlap behaviours[0] (84..84)"), std::string::npos)
        << by_address;
}

}  // namespace
}  // namespace mblab::test
