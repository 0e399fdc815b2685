// DataBank::read_be() against the plain read(): every start and length over segments of
// different accesses, so each way the copy swaps bytes (sixteen registers per step, eight, the
// last eight again over a remainder, one at a time below eight) meets every segment boundary and
// every remainder.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "device/data_bank.hpp"

namespace mblab::device {
namespace {

RangeSpec range(std::uint32_t start, std::uint32_t count, Access access) {
    RangeSpec spec;
    spec.start = start;
    spec.count = count;
    spec.access = access;
    for (std::uint32_t i = 0; i < count; ++i)
        spec.values.push_back(static_cast<std::uint16_t>(0xA100 + 0x0101 * (start + i)));
    return spec;
}

// Three segments with no hole, then a hole, then one more: 0..2 read-only, 3..21 read/write,
// 22..40 write-only, 50..89 read/write.
DataBank bank() {
    return DataBank({range(0, 3, Access::ReadOnly), range(3, 19, Access::ReadWrite),
                     range(22, 19, Access::WriteOnly), range(50, 40, Access::ReadWrite)});
}

std::vector<std::uint8_t> big_endian(const std::vector<std::uint16_t>& values) {
    std::vector<std::uint8_t> bytes;
    for (const auto value : values) {
        bytes.push_back(static_cast<std::uint8_t>(value >> 8));
        bytes.push_back(static_cast<std::uint8_t>(value & 0xFF));
    }
    return bytes;
}

void expect_read_be_as_read(const DataBank& data, std::uint32_t first, std::uint32_t end,
                            std::optional<Access> skip) {
    for (std::uint32_t address = first; address < end; ++address) {
        for (std::uint32_t count = 1; address + count <= end; ++count) {
            ASSERT_TRUE(data.find(address, count).mapped) << address << "+" << count;
            std::vector<std::uint16_t> values(count);
            data.read(address, values, skip);
            // A canary after the answer: the copy writes nothing past 2 * count bytes.
            std::vector<std::uint8_t> bytes(2 * count + 1, 0x5A);
            data.read_be(address, std::span(bytes).first(2 * count), skip);
            EXPECT_EQ(bytes.back(), 0x5A) << address << "+" << count;
            bytes.pop_back();
            EXPECT_EQ(bytes, big_endian(values)) << address << "+" << count;
        }
    }
}

TEST(DataBank, ReadBeGivesEveryStartAndLengthAsReadDoesInBigEndian) {
    const auto data = bank();
    expect_read_be_as_read(data, 0, 41, std::nullopt);
    expect_read_be_as_read(data, 50, 90, std::nullopt);
}

TEST(DataBank, ReadBeGivesZeroForTheSkippedAccessAcrossSegments) {
    const auto data = bank();
    expect_read_be_as_read(data, 0, 41, Access::WriteOnly);
    std::vector<std::uint8_t> bytes(2 * 41);
    data.read_be(0, bytes, Access::WriteOnly);
    EXPECT_EQ(bytes[2 * 21], 0xB6);  // address 21: 0xA100 + 0x0101 * 21
    EXPECT_EQ(bytes[2 * 21 + 1], 0x15);
    for (std::size_t i = 2 * 22; i < bytes.size(); ++i)
        EXPECT_EQ(bytes[i], 0) << i;
}

}  // namespace
}  // namespace mblab::device
