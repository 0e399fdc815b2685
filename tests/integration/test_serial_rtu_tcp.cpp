// RTU over TCP: RTU frames (address, PDU, CRC) on a TCP connection, answered with RTU frames,
// with serial addressing.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

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

// A client with a small window pipelines reads of 125 registers, then an FC 06 the profile
// answers by closing, then more. The answers wait in the server's socket for the window: closed
// with the client's later frames unread, the connection would be reset under them (RFC 1122
// 4.2.2.13). The server ends its output and reads on until the client ends.
TEST(RtuOverTcpClose, AnswersWaitingForTheClientsWindowArriveBeforeAnOrderlyEnd) {
    DeviceOnRtuTcp device;
    server::ServerOptions options;
    options.partial_frame_timeout = 50ms;
    ASSERT_EQ(device.start(options, "[[unit.faults]]\naction = \"close\"\nfunctions = [6]\n"), "");
    BlockingClient client(device.port(), 4096);
    ASSERT_TRUE(client.connected());
    constexpr int kAnswered = 100;
    std::vector<std::uint8_t> bytes;
    const auto append = [&](const std::string& frame) {
        const auto more = hex(frame);
        bytes.insert(bytes.end(), more.begin(), more.end());
    };
    for (int i = 0; i < kAnswered; ++i)
        append(rtu("01 03 00 00 00 7D"));
    append(rtu("01 06 00 00 00 01"));
    for (int i = 0; i < 4000; ++i)
        append(rtu("01 03 00 00 00 01"));
    ASSERT_TRUE(client.send(bytes));
    std::this_thread::sleep_for(300ms);  // the server has answered, closed and sent its end

    constexpr std::size_t kAnswer = 3 + 250 + 2;
    int answers = 0;
    while (client.read(kAnswer, 2s).size() == kAnswer)
        ++answers;
    EXPECT_EQ(answers, kAnswered);
    EXPECT_EQ(client.end_error(), 0) << std::strerror(client.end_error());
}

// A client that reads the server's end but never sends its own is let go after the linger time:
// a connection that is over cannot hold its place in the table.
TEST(RtuOverTcpClose, ServerLetsGoOfAClientThatNeverEnds) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start({}, "[[unit.faults]]\naction = \"close\"\nfunctions = [6]\n"), "");
    BlockingClient client(device.port());
    ASSERT_TRUE(client.send_hex(rtu("01 06 00 00 00 01")));
    EXPECT_TRUE(client.closed_by_peer(1s));
    EXPECT_EQ(client.end_error(), 0);
    EXPECT_EQ(device.server().stats().connections_open.load(), 1U) << "it lingers";
    const auto until = std::chrono::steady_clock::now() + 10s;
    while (device.server().stats().connections_open.load() != 0 &&
           std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(50ms);
    EXPECT_EQ(device.server().stats().connections_open.load(), 0U);
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
