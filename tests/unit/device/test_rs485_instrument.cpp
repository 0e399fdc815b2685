// The RS-485 instrument of [INSTR 5.7] on profiles/rs485-instrument.toml, byte for byte.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

using device::Link;

class Rs485Instrument : public ::testing::Test {
  protected:
    std::unique_ptr<device::ReferenceDevice> device = shipped_device("rs485-instrument");
    std::string ask(std::string_view request, std::uint8_t unit = 1) {
        return test::ask(*device, request, unit, Link::Serial);
    }
};

TEST_F(Rs485Instrument, EchoesOneToOneHundredWords) {
    EXPECT_EQ(ask("08 00 00 12 34"), "08 00 00 12 34");
    std::string hundred = "08 00 00";
    for (int i = 0; i < 100; ++i)
        hundred += " AB CD";
    EXPECT_EQ(ask(hundred), hundred);
    EXPECT_EQ(ask("08 00 00"), "88 03");
    EXPECT_EQ(ask(hundred + " 00 01"), "88 03");
}

TEST_F(Rs485Instrument, OtherSubFunctionsAreIllegalFunction) {
    EXPECT_EQ(ask("08 00 0B 00 00"), "88 01");
    EXPECT_EQ(ask("08 00 01 00 00"), "88 01");
}

TEST_F(Rs485Instrument, MeiTypeOtherThan0EIsIllegalFunction) {
    // INSTR 5.7.1: a request with 0F in place of 0E is answered AB 01
    EXPECT_EQ(ask("2B 0F 01 00"), "AB 01");
}

TEST_F(Rs485Instrument, DeviceIdCodesOneAndFourOnly) {
    EXPECT_EQ(ask("2B 0E 01 00"), "2B 0E 01 81 00 00 03 00 05 " + text_hex("mblab") + " 01 09 " +
                                      text_hex("INSTR-001") + " 02 04 " + text_hex("1.00"));
    EXPECT_EQ(ask("2B 0E 04 02"), "2B 0E 04 81 00 00 01 02 04 " + text_hex("1.00"));
    EXPECT_EQ(ask("2B 0E 02 00"), "AB 03");
    EXPECT_EQ(ask("2B 0E 03 00"), "AB 03");
}

TEST_F(Rs485Instrument, ObjectsOtherThanZeroToTwoAreIllegalDataAddress) {
    EXPECT_EQ(ask("2B 0E 04 03"), "AB 02");
    EXPECT_EQ(ask("2B 0E 01 03"), "AB 02");
    EXPECT_EQ(ask("2B 0E 04 80"), "AB 02");
}

TEST_F(Rs485Instrument, NoSelfDiagnosticsOnBroadcast) {
    EXPECT_EQ(ask("08 00 00 12 34", 0), "NO ANSWER");
    EXPECT_EQ(device->counters().stats(1)->event_count, 0);
    EXPECT_EQ(ask("06 00 03 00 07", 0), "NO ANSWER");  // a broadcast write is executed
    EXPECT_EQ(ask("03 00 03 00 01"), "03 02 00 07");
}

TEST_F(Rs485Instrument, AddressesOutsideTheProfileAreSilent) {
    EXPECT_EQ(ask("03 00 00 00 01", 2), "NO ANSWER");
    EXPECT_EQ(ask("03 00 00 00 01", 96), "NO ANSWER");
    EXPECT_EQ(ask("03 00 00 00 01", 248), "NO ANSWER");
}

TEST_F(Rs485Instrument, TypedVariablesHoldTheirInitialValues) {
    EXPECT_EQ(ask("03 00 00 00 03"), "03 06 41 C8 00 00 FF F6");  // 25.0f, -10
    EXPECT_EQ(ask("04 00 00 00 06"),
              "04 0C 41 AC 00 00 54 49 43 2D 31 30 31 00");  // 21.5f "TIC-101"
}

TEST_F(Rs485Instrument, UnsupportedFunctionsAreIllegalFunction) {
    EXPECT_EQ(ask("01 00 00 00 01"), "81 01");
    EXPECT_EQ(ask("11"), "91 01");
}

TEST_F(Rs485Instrument, ReadsOverTheDeclaredMaximumAreIllegalDataValue) {
    EXPECT_EQ(ask("03 00 00 00 41"), "83 03");
    EXPECT_EQ(device->declarations().first().max_read_registers, 64);
    EXPECT_EQ(device->declarations().first().holding_registers, 64u);
}

}  // namespace
}  // namespace mblab::test
