#include <gtest/gtest.h>

#include "protocol/lrc.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;

// The ASCII example of the serial line spec (":1103006B00037E" CR LF), a sum that wraps at 256,
// a small frame and the empty input.
TEST(Lrc, KnownVectors) {
    EXPECT_EQ(lrc(hex("11 03 00 6B 00 03")), 0x7E);
    EXPECT_EQ(lrc(hex("FF FF 02")), 0x00);
    EXPECT_EQ(lrc(hex("01 03 00 00 00 0A")), 0xF2);
    EXPECT_EQ(lrc({}), 0x00);
}

TEST(Lrc, FrameBytesPlusTheirLrcSumToZero) {
    auto bytes = hex("F7 03 13 89 00 0A");
    bytes.push_back(lrc(bytes));
    unsigned sum = 0;
    for (std::uint8_t byte : bytes)
        sum += byte;
    EXPECT_EQ(sum % 256, 0U);
}

}  // namespace
}  // namespace mblab::protocol
