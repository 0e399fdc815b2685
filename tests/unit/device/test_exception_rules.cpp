// The check order of [APP] (function 01 -> value 03 -> address 02) and the bad inputs it decides.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class ExceptionRules : public ShippedDeviceTest {
  protected:
    ExceptionRules() : ShippedDeviceTest("reference") {}
};

TEST_F(ExceptionRules, UnknownFunctionIsIllegalFunction) {
    expect_dialogue(R"(
        25 00 01 00 01 -> A5 01  # CTP 9.1.1
        41             -> C1 01
    )");
}

TEST_F(ExceptionRules, IllegalQuantityIsIllegalDataValue) {
    expect_dialogue(R"(
        03 00 00 FF FF -> 83 03  # CTP 9.1.4
        03 00 00 00 00 -> 83 03
        01 00 00 07 D1 -> 81 03
        05 00 00 12 34 -> 85 03
    )");
}

TEST_F(ExceptionRules, TruncatedOrOverlongRequestIsIllegalDataValue) {
    expect_dialogue(R"(
        03 00 00          -> 83 03
        03 00 00 00 01 00 -> 83 03
    )");
}

TEST_F(ExceptionRules, ByteCountDisagreeingWithQuantityIsIllegalDataValue) {
    expect_dialogue(R"(
        10 00 10 00 02 02 12 34             -> 90 03
        0F 00 00 00 09 01 FF                -> 8F 03
        17 00 00 00 01 00 10 00 02 02 12 34 -> 97 03
    )");
}

TEST_F(ExceptionRules, RangePastTheLastAddressIsIllegalDataAddress) {
    expect_dialogue(R"(
        03 FF FF 00 02                -> 83 02
        10 FF FF 00 02 04 00 01 00 02 -> 90 02
    )");
}

TEST_F(ExceptionRules, ReadWriteChecksTheWriteRangeBeforeWriting) {
    // CVE-2022-0367: a valid read range must not let an out-of-map write through.
    expect_dialogue(R"(
        17 00 10 00 01 FF FF 00 02 04 11 11 22 22 -> 97 02
        # Neither is a write into the read-only signature made when the read range is bad.
        17 FF FF 00 02 00 10 00 01 02 99 99       -> 97 02
        03 00 10 00 01                            -> 03 02 00 00
    )");
}

TEST_F(ExceptionRules, FileRecordOutsideTheFileIsIllegalDataAddress) {
    expect_dialogue(R"(
        14 07 06 00 02 00 63 00 02       -> 94 02  # file 2 has records 0..99
        14 07 06 00 09 00 00 00 01       -> 94 02  # no file 9
        15 09 06 00 02 00 64 00 01 00 00 -> 95 02
    )");
}

TEST_F(ExceptionRules, FileRecordWritesAreAllOrNothing) {
    expect_dialogue(R"(
        15 12 06 00 02 00 00 00 01 AA AA 06 00 02 00 64 00 01 BB BB -> 95 02
        14 07 06 00 02 00 00 00 01                                  -> 14 04 03 06 12 34
    )");
}

TEST_F(ExceptionRules, CanopenMeiIsIllegalFunction) {
    EXPECT_EQ(ask("2B 0D 00 00"), "AB 01");
}

TEST_F(ExceptionRules, UnknownDeviceIdCodeIsIllegalDataValue) {
    EXPECT_EQ(ask("2B 0E 05 00"), "AB 03");
}

TEST_F(ExceptionRules, EmptyPduGetsNoAnswer) {
    EXPECT_EQ(ask(""), "NO ANSWER");
}

TEST_F(ExceptionRules, UnsupportedFunctionComesBeforeValueChecks) {
    auto limited = device_from(R"(
[[unit]]
id = 1
functions = [1]
)");
    EXPECT_EQ(test::ask(*limited, "03 00 00 00 00"), "83 01");
    EXPECT_EQ(test::ask(*limited, "01 00 00 00 00"), "81 03");
    EXPECT_EQ(test::ask(*limited, "01 00 00 00 01"), "81 02");
}

TEST_F(ExceptionRules, DeclaredReadLimitIsIllegalDataValue) {
    auto limited = device_from(R"(
[[unit]]
id = 1
max_read_registers = 10
max_read_bits = 16
holding_registers = [{start = 0, count = 100}]
coils = [{start = 0, count = 100}]
)");
    EXPECT_EQ(test::ask(*limited, "03 00 00 00 0A").substr(0, 5), "03 14");
    EXPECT_EQ(test::ask(*limited, "03 00 00 00 0B"), "83 03");
    EXPECT_EQ(test::ask(*limited, "17 00 00 00 0B 00 00 00 01 02 00 00"), "97 03");
    EXPECT_EQ(test::ask(*limited, "01 00 00 00 11"), "81 03");
    // Quantity is checked before the address (03 before 02).
    EXPECT_EQ(test::ask(*limited, "03 FF 00 00 0B"), "83 03");
}

}  // namespace
}  // namespace mblab::test
