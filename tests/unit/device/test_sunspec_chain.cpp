// The SunSpec chain a profile builds from the model definitions ([unit.sunspec]): profiles/
// sunspec-inverter.toml, and profile text for the knobs and the errors.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class SunSpecInverter : public ShippedDeviceTest {
  protected:
    SunSpecInverter() : ShippedDeviceTest("sunspec-inverter") {}
};

TEST_F(SunSpecInverter, MarkerCommonModelAndTheChainToItsEnd) {
    expect_dialogue(R"(
        # "SunS", then model 1 of length 66 (40000 = 9C40)
        03 9C 40 00 04 -> 03 08 53 75 6E 53 00 01 00 42
        # 103 at 40070, 120 at 40122, 121 at 40150, 122 at 40182, 123 at 40228, 203 at 40254
        03 9C 86 00 02 -> 03 04 00 67 00 32
        03 9C BA 00 02 -> 03 04 00 78 00 1A
        03 9C D6 00 02 -> 03 04 00 79 00 1E
        03 9C F6 00 02 -> 03 04 00 7A 00 2C
        03 9D 24 00 02 -> 03 04 00 7B 00 18
        03 9D 3E 00 02 -> 03 04 00 CB 00 69
        # the end model at 40361
        03 9D A9 00 02 -> 03 04 FF FF 00 00
        03 9D AB 00 01 -> 83 02
    )");
}

TEST_F(SunSpecInverter, ValuesAreScaledAndUnsetPointsNotImplemented) {
    expect_dialogue(R"(
        # A 12.34 with A_SF -2, phases 4.12 4.11 4.11
        03 9C 88 00 05 -> 03 0A 04 D2 01 9C 01 9B 01 9B FF FE
        # PPVphAB..CA not implemented (uint16); W with W_SF 1, before the first update of its
        # behaviour the sine's start, its middle 5500 W
        03 9C 8D 00 03 -> 03 06 FF FF FF FF FF FF
        03 9C 94 00 02 -> 03 04 02 26 00 01
        # VAr and its scale factor not implemented (int16, sunssf), WH 1000000 Wh as 100000
        03 9C 9A 00 06 -> 03 0C 80 00 80 00 80 00 80 00 00 01 86 A0
        # Mn "mblab", NUL-padded
        03 9C 44 00 04 -> 03 08 6D 62 6C 61 62 00 00 00
    )");
}

TEST_F(SunSpecInverter, WritesAreCheckedAgainstAccessSymbolsAndLimits) {
    expect_dialogue(R"(
        # an R point (103 A) answers 02 and keeps its value
        06 9C 88 00 01 -> 86 02
        03 9C 88 00 01 -> 03 02 04 D2
        # 123 Conn: 0 and 1 are its symbols, 7 is none of them
        06 9D 28 00 07 -> 86 03
        06 9D 28 00 00 -> 06 9D 28 00 00
        03 9D 28 00 01 -> 03 02 00 00
        # 123 WMaxLimPct is limited to 0..100 %
        06 9D 29 00 65 -> 86 03
        10 9D 29 00 01 02 00 32 -> 10 9D 29 00 01
        03 9D 29 00 01 -> 03 02 00 32
        # 1 DA takes 1..247
        06 9C 84 00 00 -> 86 03
        06 9C 84 00 05 -> 06 9C 84 00 05
    )");
}

TEST_F(SunSpecInverter, ReadsThatSplitAPointAreAnsweredWhenTheProfileAccepts) {
    // The second register of WH alone.
    EXPECT_EQ(ask("03 9C 9F 00 01"), "03 02 86 A0");
}

constexpr std::string_view kChain = R"(
[[unit]]
id = 1
[unit.sunspec]
base = 0
{knobs}
[[unit.sunspec.model]]
id = 1
points = { Mn = "m", Md = "d", SN = "1" }
[[unit.sunspec.model]]
id = 123
points = { WMaxLimPct_SF = 0, WMaxLimPct = 100, Conn = "CONNECT" }
)";

std::string chain_with(std::string_view knobs) {
    std::string text(kChain);
    text.replace(text.find("{knobs}"), 7, knobs);
    return text;
}

TEST(SunSpecChain, SplitReadsRefusedWhenTheProfileSaysSo) {
    auto device = device_from(chain_with(R"(split_reads = "exception-02")"));
    // Model 1's Mn is a string of 16 registers at 4; model 123 at 70, its WMaxLimPct at 75.
    // Mn "m", NUL-padded, read whole.
    std::string whole = "03 20 6D";
    for (int i = 0; i < 31; ++i)
        whole += " 00";
    EXPECT_EQ(ask(*device, "03 00 04 00 10"), whole);
    expect_dialogue(*device, R"(
        03 00 05 00 01 -> 83 02
        10 00 05 00 01 02 41 41 -> 90 02
        03 00 4B 00 01 -> 03 02 00 64
    )");
}

TEST(SunSpecChain, KnobsForDevicesBuiltWrong) {
    auto unapplied = device_from(chain_with("writes_applied = false"));
    expect_dialogue(*unapplied, R"(
        06 00 4B 00 32 -> 06 00 4B 00 32
        03 00 4B 00 01 -> 03 02 00 64
    )");
    auto writable = device_from(chain_with("read_only_writable = true"));
    expect_dialogue(*writable, R"(
        06 00 04 41 41 -> 06 00 04 41 41
        03 00 04 00 01 -> 03 02 41 41
    )");
    auto endless = device_from(chain_with("end_model = false"));
    // Model 123 ends at 70 + 26: nothing after it.
    expect_dialogue(*endless, R"(
        03 00 46 00 02 -> 03 04 00 7B 00 18
        03 00 60 00 02 -> 83 02
    )");
}

TEST(SunSpecChain, ErrorsNameTheModelAndThePoint) {
    auto error = [](std::string_view models) {
        return profile_error(std::string("[[unit]]\nid = 1\n[unit.sunspec]\n") +
                             std::string(models));
    };
    EXPECT_NE(error("[[unit.sunspec.model]]\nid = 103\n").find("starts with the common model 1"),
              std::string::npos);
    EXPECT_NE(error("[[unit.sunspec.model]]\nid = 1\npoints = { Nope = 1 }\n")
                  .find("model 1: no point \"Nope\" to give a value"),
              std::string::npos);
    EXPECT_NE(error("[[unit.sunspec.model]]\nid = 1\n[[unit.sunspec.model]]\nid = 103\n"
                    "points = { W = 5 }\n")
                  .find("model 103: W needs a value for its scale factor W_SF"),
              std::string::npos);
    EXPECT_NE(error("[[unit.sunspec.model]]\nid = 1\n[[unit.sunspec.model]]\nid = 123\n"
                    "points = { Conn = \"MAYBE\" }\n")
                  .find("model 123: Conn has no symbol \"MAYBE\""),
              std::string::npos);
    EXPECT_NE(error("[[unit.sunspec.model]]\nid = 1\npoints = { Mn = 70000 }\n")
                  .find("Mn takes text of up to 32 characters"),
              std::string::npos);
}

}  // namespace
}  // namespace mblab::test
