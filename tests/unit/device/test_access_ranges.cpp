// Seeds 002 and 003 on profiles/access-ranges.toml: read-only, read/write and write-only
// variables, holes between ranges, and the profile options that relax the rules.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class AccessRanges : public ::testing::Test {
  protected:
    std::unique_ptr<device::ReferenceDevice> device = shipped_device("access-ranges");
    std::string ask(std::string_view request) { return test::ask(*device, request); }
};

TEST_F(AccessRanges, ReadWriteRangeReadsAndWrites) {
    EXPECT_EQ(ask("06 00 05 00 2A"), "06 00 05 00 2A");
    EXPECT_EQ(ask("03 00 05 00 01"), "03 02 00 2A");
}

TEST_F(AccessRanges, WritingReadOnlyIsIllegalDataAddress) {
    EXPECT_EQ(ask("03 00 0A 00 02"), "03 04 01 02 03 04");
    EXPECT_EQ(ask("06 00 0A 00 00"), "86 02");
    EXPECT_EQ(ask("10 00 08 00 04 08 00 01 00 02 00 03 00 04"), "90 02");
    EXPECT_EQ(ask("16 00 0A 00 00 00 00"), "96 02");
    EXPECT_EQ(ask("05 00 10 00 00"), "85 02");
    // Nothing of the refused multi-write reached the read/write part either.
    EXPECT_EQ(ask("03 00 08 00 03"), "03 06 00 00 00 00 01 02");
}

TEST_F(AccessRanges, ReadingWriteOnlyIsIllegalDataAddress) {
    EXPECT_EQ(ask("06 00 14 00 07"), "06 00 14 00 07");
    EXPECT_EQ(ask("03 00 14 00 01"), "83 02");
    EXPECT_EQ(ask("03 00 12 00 04"), "83 02");  // spans ro and wo
    EXPECT_EQ(ask("05 00 20 FF 00"), "05 00 20 FF 00");
    EXPECT_EQ(ask("01 00 20 00 01"), "81 02");
}

TEST_F(AccessRanges, HolesAreIllegalDataAddress) {
    EXPECT_EQ(ask("03 00 1E 00 01"), "83 02");
    EXPECT_EQ(ask("03 00 63 00 02"), "83 02");  // runs from the hole into 100
    EXPECT_EQ(ask("03 00 64 00 0A").substr(0, 5), "03 14");
    EXPECT_EQ(ask("03 00 64 00 0B"), "83 02");  // seed 000 9.1.2: one past the end
    EXPECT_EQ(ask("01 00 30 00 01"), "81 02");
    EXPECT_EQ(ask("02 00 00 00 09"), "82 02");
    EXPECT_EQ(ask("04 00 0A 00 01"), "84 02");
}

TEST_F(AccessRanges, AdjacentRangesReadAsOne) {
    EXPECT_EQ(ask("01 00 0E 00 04"), "01 01 0C");  // rw 14, 15 clear; ro 16, 17 set
    EXPECT_EQ(ask("02 00 00 00 08"), "02 01 85");
    EXPECT_EQ(ask("04 03 E8 00 02"), "04 04 00 01 E2 40");  // u32 123456
}

TEST(AccessPolicy, LenientProfileIgnoresWritesAndReadsZeros) {
    auto device = device_from(R"(
[[unit]]
id = 1
write_read_only = "ignore"
read_write_only = "zeros"
[[unit.holding_registers]]
start = 0
count = 2
access = "ro"
values = [7, 8]
[[unit.holding_registers]]
start = 2
count = 2
access = "wo"
values = [9, 10]
)");
    EXPECT_EQ(ask(*device, "10 00 00 00 04 08 00 01 00 02 00 03 00 04"), "10 00 00 00 04");
    EXPECT_EQ(ask(*device, "03 00 00 00 04"), "03 08 00 07 00 08 00 00 00 00");
    EXPECT_EQ(device->data().value(1, device::BankKind::HoldingRegisters, 3), 4);
}

TEST(AccessPolicy, ProfileChoosesTheExceptionCode) {
    auto device = device_from(R"(
[[unit]]
id = 1
write_read_only = "exception-04"
read_write_only = "exception-03"
[[unit.holding_registers]]
start = 0
access = "ro"
[[unit.holding_registers]]
start = 1
access = "wo"
)");
    EXPECT_EQ(ask(*device, "06 00 00 00 01"), "86 04");
    EXPECT_EQ(ask(*device, "03 00 01 00 01"), "83 03");
}

}  // namespace
}  // namespace mblab::test
