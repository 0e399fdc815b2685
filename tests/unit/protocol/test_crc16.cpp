#include <gtest/gtest.h>

#include "protocol/crc16.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;

struct Vector {
    const char* bytes;
    std::uint16_t crc;
};

// Known RTU frames (the CRC goes on the wire low byte first, so "C5 CD" is 0xCDC5), the standard
// check value of CRC-16/MODBUS over the ASCII digits "123456789", and the initial value.
constexpr Vector kVectors[] = {
    {"01 03 00 00 00 0A", 0xCDC5},
    {"11 03 00 6B 00 03", 0x8776},
    {"01 83 02", 0xF1C0},
    {"31 32 33 34 35 36 37 38 39", 0x4B37},
    {"", 0xFFFF},
};

TEST(Crc16, KnownVectors) {
    for (const Vector& vector : kVectors)
        EXPECT_EQ(crc16(hex(vector.bytes)), vector.crc) << vector.bytes;
}

TEST(Crc16, WholeFrameIncludingItsCrcGivesZero) {
    EXPECT_EQ(crc16(hex("01 03 00 00 00 0A C5 CD")), 0);
    EXPECT_NE(crc16(hex("01 03 00 00 00 0A CD C5")), 0);
}

TEST(Crc16, UpdateByteByByteMatchesWholeSpan) {
    const auto bytes = hex("11 03 00 6B 00 03");
    std::uint16_t crc = kCrc16Initial;
    for (std::uint8_t byte : bytes)
        crc = crc16_update(crc, byte);
    EXPECT_EQ(crc, crc16(bytes));
}

}  // namespace
}  // namespace mblab::protocol
