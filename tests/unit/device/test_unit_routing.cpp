// Unit ids: serial broadcast and foreign addresses, TCP unit 0 / 0xFF, several units per profile.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

using device::BankKind;
using device::Link;

TEST(SerialRules, BroadcastWritesAreExecutedAndNeverAnswered) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "06 00 10 00 05", 0, Link::Serial), "NO ANSWER");
    EXPECT_EQ(device->data().value(1, BankKind::HoldingRegisters, 0x10), 5);
    EXPECT_EQ(ask(*device, "0F 00 00 00 03 01 05", 0, Link::Serial), "NO ANSWER");
    EXPECT_EQ(ask(*device, "01 00 00 00 03", 1, Link::Serial), "01 01 05");
    EXPECT_EQ(device->counters().stats(1)->counters.no_response, 2);
}

TEST(SerialRules, BroadcastReadsAreNotExecuted) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 0, Link::Serial), "NO ANSWER");
    EXPECT_EQ(ask(*device, "08 00 04 00 00", 0, Link::Serial), "NO ANSWER");
    EXPECT_FALSE(device->counters().stats(1)->listen_only);
    // The broadcast's receive event has bit 6 set; no send event follows it.
    EXPECT_EQ(ask(*device, "0C", 1, Link::Serial), "0C 09 00 00 00 00 00 03 80 C0 C0");
}

TEST(SerialRules, OtherAddressesAreSilentButCountedOnTheBus) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 2, Link::Serial), "NO ANSWER");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 255, Link::Serial), "NO ANSWER");
    EXPECT_EQ(ask(*device, "08 00 0B 00 00", 1, Link::Serial), "08 00 0B 00 03");
    EXPECT_EQ(ask(*device, "08 00 0E 00 00", 1, Link::Serial), "08 00 0E 00 02");
}

TEST(TcpRules, UnitZeroAndFFAreAnsweredByADirectServer) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 0), "03 02 53 45");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 0xFF), "03 02 53 45");
}

// A single device answers its own unit, 0 and 0xFF [TCPG 4.4.1.2]; other unit ids get nothing,
// so a client's wrong unit id shows.
TEST(TcpRules, OtherUnitIdsAreNotAnsweredByDefault) {
    auto device = shipped_device("reference");
    for (std::uint8_t unit : {2, 7, 9, 0xF7, 0xFE})
        EXPECT_EQ(ask(*device, "03 00 00 00 01", unit), "NO ANSWER") << int{unit};
    auto plain =
        device_from("[[unit]]\nid = 5\n[[unit.holding_registers]]\nstart = 0\ncount = 4\n");
    ASSERT_TRUE(plain);
    EXPECT_EQ(ask(*plain, "03 00 00 00 01", 5), "03 02 00 00");
    EXPECT_EQ(ask(*plain, "03 00 00 00 01", 6), "NO ANSWER");
    EXPECT_EQ(plain->declarations().addressing(Link::Tcp),
              "unit 5 (0 and 255 answer as 5; other unit ids are not answered)");
    EXPECT_EQ(plain->declarations().addressing(Link::Serial),
              "address 5 (0 is a broadcast; other addresses are not answered)");
}

TEST(TcpRules, FirstUnitAnswersEveryUnitIdWhenTheProfileAsks) {
    auto device = device_from(
        "unmatched_unit = \"first-unit\"\n[[unit]]\nid = 5\n"
        "[[unit.holding_registers]]\nstart = 0\ncount = 4\n");
    ASSERT_TRUE(device);
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 7), "03 02 00 00");
    EXPECT_EQ(device->declarations().addressing(Link::Tcp),
              "unit 5 (0, 255 and every other unit id answer as 5)");
}

TEST(TcpRules, DiagnosticsAreServedOnTcp) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "08 00 00 12 34", 0xFF), "08 00 00 12 34");  // CTP 7.10
}

class MultiUnit : public ::testing::Test {
  protected:
    std::unique_ptr<device::ReferenceDevice> device = shipped_device("multi-unit");
};

TEST_F(MultiUnit, EachUnitHasItsOwnMap) {
    EXPECT_EQ(ask(*device, "04 00 00 00 02", 1), "04 04 43 66 00 00");  // 230.0f
    EXPECT_EQ(ask(*device, "01 00 00 00 08", 2), "01 01 00");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 2), "83 02");
    EXPECT_EQ(ask(*device, "03 00 64 00 01", 17), "03 02 05 DC");
    EXPECT_EQ(ask(*device, "03 00 00 00 21", 17), "83 03");
}

TEST_F(MultiUnit, EachUnitHasItsOwnIdentity) {
    EXPECT_EQ(ask(*device, "2B 0E 04 01", 2), "2B 0E 04 81 00 00 01 01 05 " + text_hex("RELAY"));
    EXPECT_EQ(ask(*device, "2B 0E 04 01", 17), "2B 0E 04 81 00 00 01 01 05 " + text_hex("DRIVE"));
}

TEST_F(MultiUnit, UnknownTcpUnitIsGatewayPathUnavailable) {
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 5), "83 0A");
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 0), "03 02 00 00");
}

TEST_F(MultiUnit, SerialBroadcastReachesEveryUnit) {
    EXPECT_EQ(ask(*device, "06 00 00 00 09", 0, Link::Serial), "NO ANSWER");
    EXPECT_EQ(device->data().value(1, BankKind::HoldingRegisters, 0), 9);
    EXPECT_EQ(device->data().value(17, BankKind::HoldingRegisters, 0), 9);
    EXPECT_EQ(ask(*device, "03 00 00 00 01", 5, Link::Serial), "NO ANSWER");
}

TEST_F(MultiUnit, ListsUnitsAndDeclarations) {
    EXPECT_EQ(device->declarations().unit_ids(), (std::vector<std::uint8_t>{1, 2, 17}));
    EXPECT_EQ(device->declarations().of(17)->max_read_registers, 32);
    EXPECT_EQ(device->declarations().of(17)->holding_registers, 50u);
    EXPECT_FALSE(device->declarations().of(5).has_value());
}

}  // namespace
}  // namespace mblab::test
