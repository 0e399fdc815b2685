// The requests the tester asks to learn whether a function is served, without changing data.
#include <gtest/gtest.h>

#include "conformance/plain_requests.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

using test::hex;

TEST(PlainRequests, ACoilIsWrittenBackAsItWasRead) {
    EXPECT_EQ(write_back_pdu(0x05, hex("01 01 01")), hex("05 00 00 FF 00"));
    EXPECT_EQ(write_back_pdu(0x05, hex("01 01 FE")), hex("05 00 00 00 00"));
    EXPECT_EQ(write_back_pdu(0x0F, hex("01 01 01")), hex("0F 00 00 00 01 01 01"));
    EXPECT_EQ(write_back_pdu(0x0F, hex("01 01 00")), hex("0F 00 00 00 01 01 00"));
    EXPECT_EQ(read_before_write_back(0x05), hex("01 00 00 00 01"));
}

TEST(PlainRequests, ARegisterIsWrittenBackAsItWasRead) {
    EXPECT_EQ(write_back_pdu(0x06, hex("03 02 BE EF")), hex("06 00 00 BE EF"));
    EXPECT_EQ(write_back_pdu(0x10, hex("03 02 BE EF")), hex("10 00 00 00 01 02 BE EF"));
    EXPECT_EQ(write_back_pdu(0x17, hex("03 02 BE EF")), hex("17 00 00 00 01 00 00 00 01 02 BE EF"));
    EXPECT_EQ(read_before_write_back(0x17), hex("03 00 00 00 01"));
}

TEST(PlainRequests, AnAnswerThatIsNotTheReadsDataGivesNoWrite) {
    EXPECT_FALSE(write_back_pdu(0x06, hex("83 02")));
    EXPECT_FALSE(write_back_pdu(0x06, hex("03 04 00 01 00 02")));
    EXPECT_FALSE(write_back_pdu(0x05, hex("03 02 00 01")));
    EXPECT_FALSE(write_back_pdu(0x03, hex("03 02 00 01")));
    EXPECT_FALSE(read_before_write_back(0x16));
}

TEST(PlainRequests, HarmlessWritesAreOnesADeviceMustRefuseWith03) {
    EXPECT_EQ(harmless_request_pdu(0x05), hex("05 00 00 12 34"));     // neither 0000 nor FF00
    EXPECT_EQ(harmless_request_pdu(0x0F), hex("0F 00 00 00 00 00"));  // quantity 0
    EXPECT_EQ(harmless_request_pdu(0x10), hex("10 00 00 00 00 00"));
    EXPECT_EQ(harmless_request_pdu(0x15), hex("15 00"));  // byte count 0
    // The mask write AND FFFF OR 0000 keeps the value: it is asked as it is.
    EXPECT_EQ(harmless_request_pdu(0x16), plain_request_pdu(0x16));
    EXPECT_EQ(harmless_request_pdu(0x03), plain_request_pdu(0x03));
}

}  // namespace
}  // namespace mblab::conformance
