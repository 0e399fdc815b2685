// Bad input a server must survive, the classes the device decides (unknown function codes,
// counts and byte counts out of range or disagreeing, addresses past the end, bad sub-functions),
// through a real socket to the reference profile. The classes the server decides alone (MBAP
// framing, lengths, unfinished and overlong frames) are in test_server_session.cpp; the framing
// ones are repeated here end to end.
#include <gtest/gtest.h>

#include "blocking_client.hpp"
#include "server_fixture.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

class ServerBadInput : public ServerFixture {
  protected:
    void SetUp() override {
        start_reference_server();
        client_ = connect();
        ASSERT_TRUE(client_.connected());
    }
    // After each bad frame the connection must still answer a good one.
    void expect_in_step() {
        EXPECT_EQ(client_.transact("7F 7F 00 00 00 06 01 03 00 00 00 01"),
                  "7F 7F 00 00 00 05 01 03 02 53 45");
    }
    BlockingClient client_;
};

TEST_F(ServerBadInput, ProtocolIdNotZeroIsDiscarded_1) {
    ASSERT_TRUE(client_.send_hex("00 01 12 34 00 06 01 03 00 00 00 01"));
    expect_in_step();
}

TEST_F(ServerBadInput, LengthLongerThanTheBytesSentIsAnswered03_2) {
    EXPECT_EQ(client_.transact("00 02 00 00 00 08 01 06 00 10"), "00 02 00 00 00 03 01 86 03");
    expect_in_step();
}

TEST_F(ServerBadInput, OversizeFrameClosesTheConnection_3) {
    std::vector<std::uint8_t> frame = hex("00 03 00 00 01 00 01 10 00 00 00 7F FE");
    frame.resize(6 + 0x100, 0x00);
    ASSERT_TRUE(client_.send(frame));
    EXPECT_TRUE(client_.closed_by_peer());
}

TEST_F(ServerBadInput, TruncatedPduIsAnswered03_4) {
    expect_exchanges(client_, {
                                  {"00 04 00 00 00 02 01 03", "00 04 00 00 00 03 01 83 03"},
                                  {"00 05 00 00 00 04 01 10 00 10", "00 05 00 00 00 03 01 90 03"},
                              });
    expect_in_step();
}

TEST_F(ServerBadInput, QuantityZeroOrOverTheLimitIsAnswered03_5) {
    expect_exchanges(client_,
                     {
                         {"00 06 00 00 00 06 01 03 00 00 00 00", "00 06 00 00 00 03 01 83 03"},
                         {"00 07 00 00 00 06 01 03 00 00 00 7E", "00 07 00 00 00 03 01 83 03"},
                         {"00 08 00 00 00 06 01 01 00 00 07 D1", "00 08 00 00 00 03 01 81 03"},
                         {"00 09 00 00 00 06 01 04 00 00 00 00", "00 09 00 00 00 03 01 84 03"},
                     });
    expect_in_step();
}

TEST_F(ServerBadInput, ByteCountThatDisagreesWithQuantityIsAnswered03_6) {
    // FC 0F: 9 coils need 2 bytes, the request says 1.
    EXPECT_EQ(client_.transact("00 0A 00 00 00 08 01 0F 00 00 00 09 01 FF"),
              "00 0A 00 00 00 03 01 8F 03");
    // FC 10: 1 register needs 2 bytes, the request says 4 (and sends 4).
    EXPECT_EQ(client_.transact("00 0B 00 00 00 0B 01 10 00 10 00 01 04 12 34 56 78"),
              "00 0B 00 00 00 03 01 90 03");
    // FC 17: 1 register to write, byte count 4.
    EXPECT_EQ(client_.transact("00 0C 00 00 00 0F 01 17 00 00 00 01 00 10 00 01 04 12 34 56 78"),
              "00 0C 00 00 00 03 01 97 03");
    expect_in_step();
}

// CVE-2022-0367: the write range of FC 17 must be checked too, not just the read range.
TEST_F(ServerBadInput, ReadWriteWithWriteRangeOutsideTheMapIsAnswered02_7) {
    EXPECT_EQ(client_.transact("00 0D 00 00 00 0F 01 17 00 10 00 01 FF FF 00 02 04 12 34 56 78"),
              "00 0D 00 00 00 03 01 97 02");
    expect_in_step();
}

TEST_F(ServerBadInput, UnknownFunctionCodeIsAnswered01_8) {
    expect_exchanges(client_, {
                                  {"00 0E 00 00 00 02 01 41", "00 0E 00 00 00 03 01 C1 01"},
                                  {"00 0F 00 00 00 04 01 25 00 01", "00 0F 00 00 00 03 01 A5 01"},
                              });
    expect_in_step();
}

// nanoMODBUS overflowed on file record sub-requests whose lengths overrun the frame.
TEST_F(ServerBadInput, FileRecordSubRequestOverrunningTheFrameIsAnException_9) {
    EXPECT_EQ(client_.transact("00 10 00 00 00 0A 01 14 0E 06 00 01 00 00 00 05"),
              "00 10 00 00 00 03 01 94 03");
    expect_in_step();
}

TEST_F(ServerBadInput, UnitIdsZeroAndFFAreAnsweredNotBroadcast_11) {
    expect_exchanges(
        client_, {
                     {"00 11 00 00 00 06 00 06 00 20 AB CD", "00 11 00 00 00 06 00 06 00 20 AB CD"},
                     {"00 12 00 00 00 06 FF 03 00 20 00 01", "00 12 00 00 00 05 FF 03 02 AB CD"},
                 });
}

TEST_F(ServerBadInput, PipelinedRequestsAreAnsweredInOrder_10) {
    ASSERT_TRUE(
        client_.send_hex("00 13 00 00 00 06 01 06 00 21 00 01"
                         "00 14 00 00 00 06 01 03 00 21 00 01"
                         "00 15 00 00 00 06 01 06 00 21 00 02"
                         "00 16 00 00 00 06 01 03 00 21 00 01"));
    EXPECT_EQ(client_.read_adu(), "00 13 00 00 00 06 01 06 00 21 00 01");
    EXPECT_EQ(client_.read_adu(), "00 14 00 00 00 05 01 03 02 00 01");
    EXPECT_EQ(client_.read_adu(), "00 15 00 00 00 06 01 06 00 21 00 02");
    EXPECT_EQ(client_.read_adu(), "00 16 00 00 00 05 01 03 02 00 02");
}

}  // namespace
}  // namespace mblab::test
