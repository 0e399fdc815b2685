// RTU over TCP: RTU frames (address, PDU, CRC) on a TCP connection, answered with RTU frames,
// with serial addressing.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "blocking_client.hpp"
#include "device/reference_device.hpp"
#include "serial_test_support.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

class RtuOverTcp : public ::testing::Test {
  protected:
    void SetUp() override {
        server::ServerOptions options;
        options.partial_frame_timeout = 50ms;
        ASSERT_EQ(device_.start(options), "");
        port_ = device_.port();
    }
    // Sends `frames` (hex) and reads as many bytes as `expected` (hex) has.
    std::string exchange(BlockingClient& client, const std::string& frames,
                         const std::string& expected) {
        if (!client.send_hex(frames)) return "send failed";
        return to_hex(client.read(hex(expected).size()));
    }

    DeviceOnRtuTcp device_;
    std::uint16_t port_ = 0;
};

TEST_F(RtuOverTcp, AnswersRtuFramesWithRtuFrames) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(exchange(client, rtu("01 10 00 64 00 02 04 12 34 56 78"), rtu("01 10 00 64 00 02")),
              rtu("01 10 00 64 00 02"));
    EXPECT_EQ(exchange(client, rtu("01 03 00 64 00 02"), rtu("01 03 04 12 34 56 78")),
              rtu("01 03 04 12 34 56 78"));
    // No length field and no silence on TCP: the echo ends where its CRC matches.
    EXPECT_EQ(exchange(client, rtu("01 08 00 00 AB CD"), rtu("01 08 00 00 AB CD")),
              rtu("01 08 00 00 AB CD"));
}

TEST_F(RtuOverTcp, AnswersFramesSentTogetherInOrderAndFramesSentByteByByte) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    const auto both = rtu("01 06 00 64 00 01") + " " + rtu("01 03 00 64 00 01");
    const auto answers = rtu("01 06 00 64 00 01") + " " + rtu("01 03 02 00 01");
    EXPECT_EQ(exchange(client, both, answers), answers);
    for (auto byte : hex(rtu("01 06 00 64 00 02"))) {
        ASSERT_TRUE(client.send(std::span(&byte, 1)));
        std::this_thread::sleep_for(2ms);
    }
    EXPECT_EQ(to_hex(client.read(8)), rtu("01 06 00 64 00 02"));
}

TEST_F(RtuOverTcp, ExecutesBroadcastsSilentlyAndIgnoresOtherAddresses) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    ASSERT_TRUE(client.send_hex(rtu("00 06 00 64 00 07")));  // broadcast: no answer
    ASSERT_TRUE(client.send_hex(rtu("05 03 00 64 00 01")));  // no unit 5: no answer
    EXPECT_EQ(exchange(client, rtu("01 03 00 64 00 01"), rtu("01 03 02 00 07")),
              rtu("01 03 02 00 07"));
}

TEST_F(RtuOverTcp, DropsGarbageAfterTheFrameTimeoutAndCountsIt) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    ASSERT_TRUE(client.send_hex("FF FF FF"));
    std::this_thread::sleep_for(200ms);  // past the 50 ms an unfinished frame may wait
    EXPECT_EQ(exchange(client, rtu("01 08 00 0C 00 00"), rtu("01 08 00 0C 00 01")),
              rtu("01 08 00 0C 00 01"));
    EXPECT_EQ(server::ServerStats::read(device_.server().stats().frames_dropped), 1u);
}

// Interop: pymodbus's TCP client with its RTU framer.
// Issue 17 item 1 over RTU framing: a frame whose bytes keep coming within the silence is still
// bounded as a whole (the 1 s frame limit); the client is closed.
TEST_F(RtuOverTcp, ClosesAClientThatTricklesAFrame) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    // FC 16 with byte count 0xF6: a 255-byte frame, sent a byte every 30 ms (7.6 s in all).
    const auto frame = hex("01 10 00 00 00 7B F6");
    bool closed = false;
    for (std::size_t i = 0; i < 150 && !closed; ++i) {
        std::uint8_t byte = i < frame.size() ? frame[i] : 0x00;
        closed = !client.send(std::span(&byte, 1)) || client.closed_by_peer(30ms);
    }
    EXPECT_TRUE(closed);
}

TEST_F(RtuOverTcp, ServesPymodbusRtuFramerOverTcp) {
    std::string output;
    const int status =
        run_command({"/usr/bin/python3",
                     std::string(MBLAB_SOURCE_DIR) + "/tests/interop/pymodbus_serial_master.py",
                     "rtu+tcp", "127.0.0.1", std::to_string(port_)},
                    output, 60s);
    EXPECT_EQ(status, 0) << output;
    EXPECT_EQ(output,
              "registers [4660, 65535, 255, 7, 65280]\n"
              "coils [True, False, True, True, False, False, True, True, True, True]\n");
}

}  // namespace
}  // namespace mblab::test
