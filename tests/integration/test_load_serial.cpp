// `mblab load` with nodes on serial lines (RTU and ASCII over pseudo-terminals) and RTU over TCP,
// beside a Modbus/TCP node: every node is judged, a silent line is counted as timeouts, and a
// broadcast address is refused.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "load_cli_support.hpp"
#include "serial_test_support.hpp"

namespace mblab::test {
namespace {

std::string line_url(const std::string& scheme, const std::string& path, unsigned baud) {
    return scheme + "://" + path + "?baud=" + std::to_string(baud) + "&data=8";
}

TEST(LoadSerial, RtuAndAsciiLinesPassBesideATcpNode) {
    DeviceOnLine rtu;
    ASSERT_EQ(rtu.start("reference", "rtu", 9600, false), "");
    DeviceOnLine ascii;
    ASSERT_EQ(ascii.start("reference", "ascii", 115200, false), "");
    Device tcp;
    const auto rtu_url = line_url("rtu", rtu.pty().client_end(), 9600);
    const auto ascii_url = line_url("ascii", ascii.pty().client_end(), 115200);
    auto run =
        mblab_load("lines", {tcp.url(), rtu_url, ascii_url, "--duration", "2s", "--connections",
                             "6", "--registers", "65536", "--timeout", "3000"});
    EXPECT_EQ(run.status, 0) << run.out << run.err;
    ASSERT_EQ(run.report["nodes"].size(), 3U) << run.out;
    for (const auto& node : run.report["nodes"]) {
        expect_clean(node);
        // Each node got its protocol tests and its share of the generator's mix (FC 03 x125 is
        // in both).
        EXPECT_GT(sent_with_function(node, 0x03), 0U) << node.dump(2);
        EXPECT_GT(sent_with_function(node, 0x10), 0U) << node.dump(2);
    }
    // Each line's use against what its baud rate carries; ASCII frames need no silence between
    // them, so its limit is the baud rate over 11 bits (8E1) a character.
    EXPECT_TRUE(run.report["nodes"][0]["line"].is_null());
    const auto& rtu_line = run.report["nodes"][1]["line"];
    ASSERT_TRUE(rtu_line.is_object()) << run.report["nodes"][1].dump(2);
    EXPECT_GT(rtu_line["limit_per_s"].get<double>(), 0.0);
    EXPECT_LT(rtu_line["limit_per_s"].get<double>(), 9600.0 / 11);
    EXPECT_TRUE(rtu_line["logical_timing"].get<bool>());
    const auto& ascii_line = run.report["nodes"][2]["line"];
    ASSERT_TRUE(ascii_line.is_object());
    EXPECT_NEAR(ascii_line["limit_per_s"].get<double>(), 115200.0 / 11, 0.5);
    EXPECT_NEAR(ascii_line["share"].get<double>(),
                ascii_line["characters_per_s"].get<double>() / (115200.0 / 11), 0.01);
    EXPECT_NE(run.out.find("rtu://" + rtu.pty().client_end() +
                           "?baud=9600&parity=E&stop=1&data=8: line use "),
              std::string::npos)
        << run.out;
    EXPECT_NE(run.out.find("with t3.5 between frames (a pty passes bytes on at once: pace=1 on "
                           "both ends keeps a line's timing)"),
              std::string::npos)
        << run.out;
    // The lines are named as given, settings spelled out.
    EXPECT_EQ(run.report["nodes"][1]["target"],
              "rtu://" + rtu.pty().client_end() + "?baud=9600&parity=E&stop=1&data=8");
}

TEST(LoadSerial, RtuOverTcpNodePasses) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    auto run = mblab_load("rtu_tcp", {"rtu+tcp://127.0.0.1:" + std::to_string(device.port()),
                                      "--duration", "1s", "--registers", "65536"});
    EXPECT_EQ(run.status, 0) << run.out << run.err;
    ASSERT_EQ(run.report["nodes"].size(), 1U) << run.out;
    expect_clean(run.report["nodes"][0]);
}

TEST(LoadSerial, ALineWithoutADeviceFailsWithTimeouts) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    RawSerialMaster other_end(pty.server_end());  // holds the line open; never answers
    ASSERT_TRUE(other_end.ok());
    auto run = mblab_load("silent", {line_url("rtu", pty.client_end(), 19200), "--duration", "1s",
                                     "--timeout", "200", "--connections", "0"});
    EXPECT_EQ(run.status, 1) << run.out << run.err;
    ASSERT_EQ(run.report["nodes"].size(), 1U) << run.out;
    const auto& node = run.report["nodes"][0];
    EXPECT_EQ(node["verdict"], "FAIL");
    EXPECT_GT(failures(node, "timeout"), 0U);
    EXPECT_EQ(node["failures"]["total"], failures(node, "timeout"));
    EXPECT_EQ(node["answers"], 0);
    EXPECT_EQ(node["first_failure"]["kind"], "timeout") << node.dump(2);
    EXPECT_EQ(node["first_failure"]["exchange"], "7.3.1") << node.dump(2);
}

TEST(LoadSerial, TheBroadcastAddressIsRefused) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    const auto url = line_url("rtu", pty.client_end(), 19200);
    auto run = mblab_load("broadcast", {url, "--unit", "0", "--duration", "1s"});
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.err, "mblab load: unit 0 is not a serial device address: on rtu://" +
                           pty.client_end() +
                           "?baud=19200&parity=E&stop=1&data=8 a device answers at an address "
                           "from 1 to 247 (0 is the broadcast); give it with --unit\n");
}

}  // namespace
}  // namespace mblab::test
