// A load run's use of a serial line against what its baud rate carries: characters of 11 bits
// (8E1) or 10 (7E1, 8N1), and t3.5 of silence between RTU frames [SER 2.5.1.1].
#include <gtest/gtest.h>

#include "load/line_use.hpp"

namespace mblab::load {
namespace {

using std::chrono::microseconds;
using std::chrono::seconds;

transport::SerialUrl line(transport::SerialUrl::Kind kind, unsigned baud) {
    transport::SerialUrl url;
    url.kind = kind;
    url.line.device = "/dev/mblab-test-line";  // not a pty: the timing is the line's own
    url.line.baud = baud;
    return url;
}

TEST(LineUse, RtuFramesNeedTheirSilenceBetweenThem) {
    // 100 exchanges of FC 03 x1 at 19200 8E1: 8 + 7 characters, 2 frames each. A character is
    // 572.9 us and t3.5 is 2006 us, so 1500 characters and 200 silences fill 1.2606 s.
    const auto url = line(transport::SerialUrl::Kind::Rtu, 19200);
    const auto use = line_use(url, 1500, 200, microseconds(2'521'200));
    ASSERT_TRUE(use);
    EXPECT_NEAR(use->limit_per_second, 1500 / 1.2606, 0.5);
    EXPECT_NEAR(use->chars_per_second, 1500 / 2.5212, 0.01);
    EXPECT_NEAR(use->share, 0.5, 0.001);
    EXPECT_FALSE(use->logical);
    EXPECT_EQ(line_use_text(url, *use),
              "595 characters/s, 50.0% of the 1190/s 19200 baud allows with t3.5 between frames");
}

TEST(LineUse, AsciiFramesNeedNoSilenceAndAFasterLineHasAFixedOne) {
    auto ascii = line(transport::SerialUrl::Kind::Ascii, 9600);
    ascii.line.data_bits = 7;  // 7E1: 10 bits, 960 characters/s
    const auto full = line_use(ascii, 960, 20, seconds(1));
    ASSERT_TRUE(full);
    EXPECT_NEAR(full->limit_per_second, 960.0, 0.01);
    EXPECT_NEAR(full->share, 1.0, 0.001);
    EXPECT_EQ(line_use_text(ascii, *full),
              "960 characters/s, 100.0% of the 960/s 9600 baud allows");
    // Above 19200 baud t3.5 is 1750 us whatever the rate: at 115200 8E1 a character is 95.5 us.
    const auto fast =
        line_use(line(transport::SerialUrl::Kind::Rtu, 115200), 1000, 100, seconds(1));
    ASSERT_TRUE(fast);
    EXPECT_NEAR(fast->limit_per_second, 1000 / (1000 * 11 / 115200.0 + 100 * 1750e-6), 0.5);
}

TEST(LineUse, NothingWithoutABaudRateOrWithoutTraffic) {
    EXPECT_FALSE(
        line_use(line(transport::SerialUrl::Kind::RtuOverTcp, 19200), 100, 10, seconds(1)));
    EXPECT_FALSE(line_use(line(transport::SerialUrl::Kind::Rtu, 19200), 0, 0, seconds(1)));
}

}  // namespace
}  // namespace mblab::load
