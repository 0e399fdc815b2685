#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "serial_test_support.hpp"
#include "support/hex.hpp"
#include "support/ports.hpp"
#include "test_client_support.hpp"

// The client's serial links: RTU and ASCII on a pseudo-terminal line, RTU over TCP, each against
// the reference device served by mblab's own serial servers; and a broken RTU answer.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

const std::string kSignature =
    "address     raw     u16\n"
    "0 (0x0000)  0x5345  21317\n"
    "1 (0x0001)  0x4D49  19785\n";

std::string line_url(const std::string& scheme, const PtyPair& pty, unsigned baud = 19200) {
    return scheme + "://" + pty.client_end() + "?baud=" + std::to_string(baud) + "&data=8";
}

// `mblab ARGS...` with a timeout a loaded machine cannot miss.
Ran on_line(std::vector<std::string> args) {
    args.insert(args.end(), {"--timeout", "3000"});
    return run_mblab(args);
}

// The line's speed, for the tests that run at 9600 and at 115200 baud.
class ClientSerialAt : public ::testing::TestWithParam<unsigned> {};

TEST_P(ClientSerialAt, ReadsAndWritesOverRtu) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", GetParam(), false), "");
    const auto url = line_url("rtu", line.pty(), GetParam());
    auto read = on_line({"read", url, "holding", "0", "2", "--decode", "bytes"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(read.out, kSignature);
    EXPECT_EQ(read.err,
              "> 01 03 00 00 00 02 C4 0B\n"
              ">   address 1\n"
              ">   function 0x03 read holding registers: starting address 0 (0x0000), "
              "quantity 2\n"
              "< 01 03 04 53 45 4D 49 0E 04\n"
              "<   address 1\n"
              "<   function 0x03 read holding registers: byte count 4, registers 0x5345 0x4D49\n");
    ASSERT_EQ(on_line({"write", url, "registers", "100", "1.5", "--type", "f32"}).status, 0);
    EXPECT_EQ(on_line({"read", url, "holding", "100", "--type", "f32"}).out,
              "address       raw            f32\n100 (0x0064)  0x3FC0 0x0000  1.5\n");
    // An echo has no length in its layout: the line's silence ends it.
    EXPECT_EQ(on_line({"diag", url, "query-data", "1", "2", "3"}).out,
              "echoed 6 bytes: 00 01 00 02 00 03\n");
}

TEST_P(ClientSerialAt, ReadsOverAscii) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "ascii", GetParam(), false), "");
    const auto url = line_url("ascii", line.pty(), GetParam());
    auto read = on_line({"read", url, "holding", "0", "2"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(read.out, kSignature);
    auto devid = on_line({"devid", url, "vendor-name"});
    EXPECT_EQ(devid.out,
              "conformity level 0x83 (extended, individual access)\n"
              "0x00  vendor name  mblab\n");
}

INSTANTIATE_TEST_SUITE_P(Baud, ClientSerialAt, ::testing::Values(9600U, 115200U),
                         [](const auto& info) { return std::to_string(info.param); });

// pace=1 on both ends: each side sends one character per character time, as a UART would, and
// the exchange goes through whole. 1200 baud makes t3.5 32 ms, a silence no busy machine opens
// by accident between two characters.
TEST(ClientSerial, PacedEndsKeepALinesTimingAndStillExchangeWholeFrames) {
    for (const std::string scheme : {"rtu", "ascii"}) {
        DeviceOnLine line;
        ASSERT_EQ(line.start("reference", scheme, 1200, false, "&pace=1"), "");
        const auto url = line_url(scheme, line.pty(), 1200) + "&pace=1";
        auto read = on_line({"read", url, "holding", "0", "2"});
        EXPECT_EQ(read.status, 0) << scheme << ": " << read.err;
        EXPECT_EQ(read.out, kSignature) << scheme;
        EXPECT_EQ(on_line({"write", url, "register", "100", "4660"}).status, 0) << scheme;
        EXPECT_EQ(on_line({"read", url, "holding", "100"}).out,
                  "address       raw     u16\n100 (0x0064)  0x1234  4660\n")
            << scheme;
    }
    // The pacing itself: 60 registers are 125 answer characters from the device, and 129
    // request characters from the client, 9.17 ms each at 1200 8E1. A lower bound only: a
    // slow machine can only make these take longer.
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 1200, false, "&pace=1"), "");
    const auto url = line_url("rtu", line.pty(), 1200) + "&pace=1";
    const auto timed = [](const std::vector<std::string>& args) {
        const auto start = std::chrono::steady_clock::now();
        EXPECT_EQ(on_line(args).status, 0);
        return std::chrono::steady_clock::now() - start;
    };
    EXPECT_GE(timed({"read", url, "holding", "0", "60"}), std::chrono::milliseconds(1146));
    std::vector<std::string> write = {"write", url, "registers", "200"};
    write.insert(write.end(), 60, "7");
    EXPECT_GE(timed(write), std::chrono::milliseconds(1182));
}

TEST(ClientSerial, BroadcastsAreRefused) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 19200, false), "");
    auto ran =
        run_mblab({"write", line_url("rtu", line.pty()), "register", "1", "1", "--unit", "0"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err,
              "mblab write: unit 0 is the broadcast address of a serial line, which no "
              "device answers; mblab does not send broadcasts\n");
}

TEST(ClientSerial, ABadCrcIsABadAnswer) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    RawSerialMaster device(pty.server_end());  // the test plays the device on the other end
    ASSERT_TRUE(device.ok());
    ChildProcess client(
        {MBLAB_BINARY, "read", line_url("rtu", pty), "holding", "0", "--timeout", "2000"});
    EXPECT_EQ(to_hex(device.receive()), "01 03 00 00 00 01 84 0A");
    device.send(hex("01 03 02 00 2A 00 00"));
    EXPECT_EQ(client.wait_exit(std::chrono::seconds(10)), 1);
    EXPECT_EQ(client.drain_stderr(),
              "mblab read: bad answer: CRC mismatch: frame has 0x0000, computed 0x9B39\n");
}

TEST(ClientSerial, ReadsOverRtuOverTcp) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    const std::string url = "rtu+tcp://127.0.0.1:" + std::to_string(device.port());
    auto read = on_line({"read", url, "holding", "0", "2"});
    auto echo = on_line({"diag", url, "query-data", "0xABCD"});
    auto json = on_line({"read", url, "coils", "0", "--json"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(read.out, kSignature);
    EXPECT_EQ(echo.out, "echoed 2 bytes: AB CD\n");
    EXPECT_NE(json.out.find("\"target\": \"" + url + "\""), std::string::npos) << json.out;
}

TEST(ClientSerial, UnreachableSerialTargets) {
    auto missing = run_mblab({"read", "rtu:///dev/mblab-no-such-port", "holding", "0"});
    EXPECT_EQ(missing.status, 2);
    EXPECT_EQ(missing.err.rfind("mblab read: cannot connect to rtu:///dev/mblab-no-such-port?", 0),
              0U)
        << missing.err;
    auto refused =
        run_mblab({"read", "rtu+tcp://127.0.0.1:" + std::to_string(closed_port()), "holding", "0"});
    EXPECT_EQ(refused.status, 2);
    EXPECT_THAT(refused.err, HasSubstr(": connection refused\n"));
}

}  // namespace
}  // namespace mblab::test
