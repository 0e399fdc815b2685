// The RS-485 instrument of [INSTR 5.7] (profiles/rs485-instrument.toml) on a serial line, RTU and
// ASCII: the FC 08 echo and FC 2B/0E limits it documents, and the addresses it ignores. The test is
// the serial master, writing frames byte by byte.
#include <gtest/gtest.h>

#include <string>

#include "serial_test_support.hpp"

namespace mblab::test {
namespace {

// "00 01 00 02 ..": `words` data words counting up from 1.
std::string counting_words(int words) {
    std::string out;
    for (int i = 1; i <= words; ++i) {
        char text[8];
        std::snprintf(text, sizeof text, " %02X %02X", (i >> 8) & 0xFF, i & 0xFF);
        out += text;
    }
    return out;
}

class Rs485InstrumentLine : public ::testing::TestWithParam<const char*> {
  protected:
    void SetUp() override {
        auto error = line_.start("rs485-instrument", GetParam());
        ASSERT_EQ(error, "");
    }
    DeviceOnLine line_;
};

TEST_P(Rs485InstrumentLine, EchoesOneAndOneHundredDataWords) {
    EXPECT_EQ(line_.ask("01 08 00 00 12 34"), line_.wire("01 08 00 00 12 34"));
    const auto hundred = "01 08 00 00" + counting_words(100);
    EXPECT_EQ(line_.ask(hundred), line_.wire(hundred));
}

TEST_P(Rs485InstrumentLine, RefusesEchoOfNoWordsOrOverOneHundredWithException03) {
    EXPECT_EQ(line_.ask("01 08 00 00"), line_.wire("01 88 03"));
    EXPECT_EQ(line_.ask("01 08 00 00" + counting_words(101)), line_.wire("01 88 03"));
}

TEST_P(Rs485InstrumentLine, ReadsBasicIdentificationAsAStreamAndObjectByObject) {
    // vendor "mblab", product code "INSTR-001", revision "1.00"; conformity 81: basic
    // identification, stream and individual access.
    EXPECT_EQ(line_.ask("01 2B 0E 01 00"), line_.wire("01 2B 0E 01 81 00 00 03"
                                                      " 00 05 6D 62 6C 61 62"
                                                      " 01 09 49 4E 53 54 52 2D 30 30 31"
                                                      " 02 04 31 2E 30 30"));
    EXPECT_EQ(line_.ask("01 2B 0E 04 00"),
              line_.wire("01 2B 0E 04 81 00 00 01 00 05 6D 62 6C 61 62"));
    EXPECT_EQ(line_.ask("01 2B 0E 04 01"),
              line_.wire("01 2B 0E 04 81 00 00 01 01 09 49 4E 53 54 52 2D 30 30 31"));
    EXPECT_EQ(line_.ask("01 2B 0E 04 02"), line_.wire("01 2B 0E 04 81 00 00 01 02 04 31 2E 30 30"));
}

TEST_P(Rs485InstrumentLine, RefusesOtherObjectsWith02AndOtherReadCodesWith03) {
    EXPECT_EQ(line_.ask("01 2B 0E 04 03"), line_.wire("01 AB 02"));
    EXPECT_EQ(line_.ask("01 2B 0E 04 80"), line_.wire("01 AB 02"));
    EXPECT_EQ(line_.ask("01 2B 0E 01 03"), line_.wire("01 AB 02"));
    EXPECT_EQ(line_.ask("01 2B 0E 02 00"), line_.wire("01 AB 03"));
    EXPECT_EQ(line_.ask("01 2B 0E 03 00"), line_.wire("01 AB 03"));
    EXPECT_EQ(line_.ask("01 2B 0E 05 00"), line_.wire("01 AB 03"));
}

// Seed 001: a wrong MEI type ("sub-function") is answered AB 01.
TEST_P(Rs485InstrumentLine, RefusesOtherMeiTypeWith01) {
    EXPECT_EQ(line_.ask("01 2B 0F 01 00"), line_.wire("01 AB 01"));
}

// Address 0 is a broadcast, which self-diagnostics ignore; 96 is outside 1..95. Neither is
// answered, and the line stays in step: the next request gets exactly its own answer.
TEST_P(Rs485InstrumentLine, AnswersNeitherBroadcastNorAddressOutsideItsRange) {
    EXPECT_EQ(line_.ask("00 08 00 00 12 34", 300ms), "");
    EXPECT_EQ(line_.ask("60 08 00 00 12 34", 300ms), "");
    EXPECT_EQ(line_.ask("00 2B 0E 01 00", 300ms), "");
    EXPECT_EQ(line_.ask("60 2B 0E 01 00", 300ms), "");
    EXPECT_EQ(line_.ask("01 08 00 00 AB CD"), line_.wire("01 08 00 00 AB CD"));
}

INSTANTIATE_TEST_SUITE_P(Framing, Rs485InstrumentLine, ::testing::Values("rtu", "ascii"),
                         [](const auto& info) { return std::string(info.param); });

}  // namespace
}  // namespace mblab::test
