// Seeds 002 and 003 on profiles/access-ranges.toml: read-only, read/write and write-only
// variables, holes between ranges, and the profile options that relax the rules.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class AccessRanges : public ShippedDeviceTest {
  protected:
    AccessRanges() : ShippedDeviceTest("access-ranges") {}
};

TEST_F(AccessRanges, ReadWriteRangeReadsAndWrites) {
    expect_dialogue(R"(
        06 00 05 00 2A -> 06 00 05 00 2A
        03 00 05 00 01 -> 03 02 00 2A
    )");
}

TEST_F(AccessRanges, WritingReadOnlyIsIllegalDataAddress) {
    expect_dialogue(R"(
        03 00 0A 00 02                            -> 03 04 01 02 03 04
        06 00 0A 00 00                            -> 86 02
        10 00 08 00 04 08 00 01 00 02 00 03 00 04 -> 90 02
        16 00 0A 00 00 00 00                      -> 96 02
        05 00 10 00 00                            -> 85 02
        # Nothing of the refused multi-write reached the read/write part either.
        03 00 08 00 03                            -> 03 06 00 00 00 00 01 02
    )");
}

TEST_F(AccessRanges, ReadingWriteOnlyIsIllegalDataAddress) {
    expect_dialogue(R"(
        06 00 14 00 07 -> 06 00 14 00 07
        03 00 14 00 01 -> 83 02
        03 00 12 00 04 -> 83 02  # spans ro and wo
        05 00 20 FF 00 -> 05 00 20 FF 00
        01 00 20 00 01 -> 81 02
    )");
}

TEST_F(AccessRanges, HolesAreIllegalDataAddress) {
    expect_dialogue(R"(
        03 00 1E 00 01 -> 83 02
        03 00 63 00 02 -> 83 02  # runs from the hole into 100
    )");
    EXPECT_EQ(ask("03 00 64 00 0A").substr(0, 5), "03 14");
    expect_dialogue(R"(
        03 00 64 00 0B -> 83 02  # CTP 9.1.2: one past the end
        01 00 30 00 01 -> 81 02
        02 00 00 00 09 -> 82 02
        04 00 0A 00 01 -> 84 02
    )");
}

TEST_F(AccessRanges, AdjacentRangesReadAsOne) {
    expect_dialogue(R"(
        01 00 0E 00 04 -> 01 01 0C  # rw 14, 15 clear; ro 16, 17 set
        02 00 00 00 08 -> 02 01 85
        04 03 E8 00 02 -> 04 04 00 01 E2 40  # u32 123456
    )");
}

// Unit 1 with `holding` registers and the profile's answers to writes of read-only and reads
// of write-only registers.
std::unique_ptr<device::ReferenceDevice> with_policy(std::string_view write_read_only,
                                                     std::string_view read_write_only,
                                                     std::string_view holding) {
    return device_from("[[unit]]\nid = 1\nwrite_read_only = \"" + std::string(write_read_only) +
                       "\"\nread_write_only = \"" + std::string(read_write_only) +
                       "\"\nholding_registers = " + std::string(holding) + "\n");
}

TEST(AccessPolicy, LenientProfileIgnoresWritesAndReadsZeros) {
    auto device = with_policy("ignore", "zeros",
                              R"([{start = 0, count = 2, access = "ro", values = [7, 8]},
                                  {start = 2, count = 2, access = "wo", values = [9, 10]}])");
    expect_dialogue(*device, R"(
        10 00 00 00 04 08 00 01 00 02 00 03 00 04 -> 10 00 00 00 04
        03 00 00 00 04                            -> 03 08 00 07 00 08 00 00 00 00
    )");
    EXPECT_EQ(device->data().value(1, device::BankKind::HoldingRegisters, 3), 4);
}

TEST(AccessPolicy, ProfileChoosesTheExceptionCode) {
    auto device = with_policy("exception-04", "exception-03",
                              R"([{start = 0, access = "ro"}, {start = 1, access = "wo"}])");
    expect_dialogue(*device, R"(
        06 00 00 00 01 -> 86 04
        03 00 01 00 01 -> 83 03
    )");
}

}  // namespace
}  // namespace mblab::test
