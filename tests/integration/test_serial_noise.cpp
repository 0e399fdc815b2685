// Noise on a serial line [SER 2.4.2, 6.1]: random bytes, truncated frames,
// bad checks, each alone between silences. Each is dropped, the good frame after it is served,
// and FC 08 sub 0C (bus communication errors) counts every one.
#include <gtest/gtest.h>

#include <string>

#include "serial_test_support.hpp"

namespace mblab::test {
namespace {

class NoisyLine : public ::testing::Test {
  protected:
    void start(const char* scheme) { ASSERT_EQ(line_.start("reference", scheme), ""); }
    // A good request (unit 1, holding register 0x10) answered exactly: nothing of the noise
    // before it leaked into the frame or the answer.
    void expect_served(const std::string& value) {
        EXPECT_EQ(line_.ask("01 06 00 10 " + value), line_.wire("01 06 00 10 " + value));
        EXPECT_EQ(line_.ask("01 03 00 10 00 01"), line_.wire("01 03 02 " + value));
    }
    DeviceOnLine line_;
};

TEST_F(NoisyLine, RtuDropsNoiseKeepsTheNextFrameAndCountsEachBurst) {
    start("rtu");
    expect_served("11 11");
    line_.send_raw_hex(  // 32 random bytes
        "A5 4D CA 18 25 30 BB 1D 6D 13 2C DE D6 23 7B 2E D9 1E 3F 72 1F CB 19 71 17 44 94 D6 49 3C "
        "9D 5C");
    expect_served("22 22");
    line_.send_raw_hex("01 03 00 10 00 01");  // a frame without its CRC
    expect_served("33 33");
    line_.send_raw_hex("01 03 00 10 00 01 85 CE");  // CRC off by one bit (good: 85 CF)
    expect_served("44 44");
    line_.send_raw_hex("01 03");  // under the 4 bytes of the shortest frame
    expect_served("55 55");
    line_.send_raw_hex("01 06 00 10 12");  // a write cut off mid-value
    expect_served("66 66");
    EXPECT_EQ(line_.ask("01 08 00 0C 00 00"), line_.wire("01 08 00 0C 00 05"));
}

// The CRC in the test above is checked against the frame the framer builder makes.
TEST(RtuFrameBuilder, AppendsTheCrcOfTheSpecExample) {
    EXPECT_EQ(rtu("01 03 00 10 00 01"), "01 03 00 10 00 01 85 CF");
    EXPECT_EQ(rtu("01 03 00 00 00 01"), "01 03 00 00 00 01 84 0A");
}

TEST_F(NoisyLine, AsciiDropsBadFramesKeepsTheNextAndCountsEach) {
    start("ascii");
    expect_served("11 11");
    line_.send_raw_text(":01030010000100\r\n");  // LRC 00 instead of EB
    expect_served("22 22");
    line_.send_raw_text(
        ":01030G10000"
        "1EB\r\n");  // 'G' is not hex
    expect_served("33 33");
    line_.send_raw_text("#&*!~");  // outside a frame: skipped, not an error
    expect_served("44 44");
    line_.send_raw_text(":010300");  // cut short; the next ':' ends it
    expect_served("55 55");
    line_.send_raw_text(":0103001000");  // cut short; the 1 s inter-character timeout ends it
    std::this_thread::sleep_for(1200ms);
    expect_served("66 66");
    EXPECT_EQ(line_.ask("01 08 00 0C 00 00"), line_.wire("01 08 00 0C 00 04"));
}

TEST(AsciiFrameBuilder, AppendsTheLrc) {
    EXPECT_EQ(ascii("01 03 00 10 00 01"), ":010300100001EB\r\n");
}

}  // namespace
}  // namespace mblab::test
