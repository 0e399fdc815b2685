// `mblab fuzz` over a serial line: `mblab serve` on one end of a pty pair, the fuzzer on the
// other, in RTU and in ASCII. Our own server must show no finding; the report says which classes
// were tried on the line and why the MBAP ones were not. A device that goes deaf on one line
// input is found and minimised to that frame.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "child_process.hpp"
#include "serial_test_support.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using namespace std::chrono_literals;

// tshark's option that decodes LINKTYPE_USER0, where mblab writes a line's frames, as Modbus RTU.
constexpr const char* kUser0IsModbusRtu =
    R"x(uat:user_dlts:"User 0 (DLT=147)","mbrtu","0","","0","")x";

nlohmann::json class_row(const nlohmann::json& report, const std::string& name) {
    for (const auto& row : report["classes"]) {
        if (row["class"] == name) return row;
    }
    return {};
}

void fuzz_serve_over(const std::string& scheme) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    const std::string settings = "?baud=115200&data=8";
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "--listen", scheme + "://" + pty.server_end() + settings});
    const auto started = serve.read_stdout_line(10s).value_or("");
    ASSERT_NE(started.find("mblab serve:"), std::string::npos) << started;
    TempDir dir;
    const auto json = (dir.path() / "fuzz.json").string();
    const auto ran = run_mblab({"fuzz", scheme + "://" + pty.client_end() + settings, "--cases",
                                "150", "--rate", "0", "--timeout", "500", "--json", json});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding: the device served every liveness check"));
    EXPECT_THAT(ran.out,
                HasSubstr("  protocol-id         n/a an MBAP header field: a serial line has "
                          "none\n"));
    const auto report = nlohmann::json::parse(file_text(json), nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << ran.out;
    EXPECT_EQ(report["cases"], 150) << ran.out;
    for (const auto* name : {"frame-check", "short-frame", "noise", "quantity", "unit-id",
                             "unknown-function", "oversize", "truncated"}) {
        EXPECT_GT(class_row(report, name)["run"].get<int>(), 0) << name << "\n" << ran.out;
    }
    for (const auto* name : {"protocol-id", "mbap-length", "partial-header", "many-connections",
                             "pipelined", "split-frame"}) {
        EXPECT_EQ(class_row(report, name)["run"], 0) << name;
        EXPECT_NE(class_row(report, name)["not_applicable"], "") << name;
    }
    const std::string own = scheme == "rtu" ? "line-gap" : "ascii-text";
    EXPECT_GT(class_row(report, own)["run"].get<int>(), 0) << ran.out;
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
}

TEST(FuzzSerial, ServeOverRtuHasNoFinding) {
    fuzz_serve_over("rtu");
}

TEST(FuzzSerial, ServeOverAsciiHasNoFinding) {
    fuzz_serve_over("ascii");
}

// RTU frames over a TCP connection: the line's cases, one connection for the run.
TEST(FuzzSerial, RtuOverTcpHasNoFinding) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    const auto ran = run_mblab({"fuzz", "rtu+tcp://127.0.0.1:" + std::to_string(device.port()),
                                "--cases", "150", "--rate", "0", "--timeout", "500"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding: the device served every liveness check"));
    EXPECT_THAT(ran.out, HasSubstr("  line-gap              2 run\n"));
    EXPECT_THAT(ran.out, HasSubstr("  many-connections    n/a a serial line is one connection\n"));
}

// `--pcap` on a line: every frame of the run, the tester's outbound and the device's inbound,
// which tshark decodes as Modbus RTU queries and responses.
TEST(FuzzSerial, APcapOfALineRunHoldsItsFramesBothWays) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "--listen", "rtu://" + pty.server_end() + "?baud=115200&data=8"});
    ASSERT_TRUE(serve.read_stdout_line(10s).has_value());
    TempDir dir;
    const auto pcap = (dir.path() / "run.pcapng").string();
    const auto ran = run_mblab({"fuzz", "rtu://" + pty.client_end() + "?baud=115200&data=8",
                                "--cases", "20", "--rate", "0", "--pcap", pcap});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    std::string decoded;
    ASSERT_EQ(run_command({"tshark", "-o", kUser0IsModbusRtu, "-r", pcap, "-T", "fields", "-e",
                           "frame.p2p_dir", "-e", "mbrtu.unit_id", "-e", "modbus.func_code"},
                          decoded),
              0)
        << decoded;
    // Sent (p2p_dir 0: outbound) reads and received (1: inbound) answers, unit 1, FC 03.
    EXPECT_THAT(decoded, HasSubstr("0\t1\t3\n")) << decoded.substr(0, 2000);
    EXPECT_THAT(decoded, HasSubstr("1\t1\t3\n")) << decoded.substr(0, 2000);
    // The command docs/robustness.md prints, as printed, in the directory of run.pcapng.
    const auto doc = file_text(std::string(MBLAB_SOURCE_DIR) + "/docs/robustness.md");
    const auto at = doc.find("tshark -o 'uat:user_dlts:");
    ASSERT_NE(at, std::string::npos);
    const auto command = doc.substr(at, doc.find('\n', at) - at);
    std::string printed;
    EXPECT_EQ(run_command({"sh", "-c", "cd " + dir.path().string() + " && " + command}, printed), 0)
        << command << "\n"
        << printed;
    EXPECT_THAT(printed, HasSubstr("Modbus RTU")) << printed.substr(0, 2000);
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
}

// `mblab serve` over RTU over TCP closes a connection on a frame longer than any RTU frame: its
// right on TCP. The check then asks on a fresh connection rather than call the device dead.
TEST(FuzzSerial, ServeOverRtuTcpClosingOnAnOversizeFrameIsNotAFinding) {
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "rtu+tcp://127.0.0.1:0"});
    std::smatch match;
    const auto line = serve.read_stdout_line(10s).value_or("");
    ASSERT_TRUE(std::regex_search(line, match, std::regex("rtu\\+tcp://127\\.0\\.0\\.1:[0-9]+")))
        << line;
    const auto ran = run_mblab({"fuzz", match[0], "--cases", "40", "--rate", "0"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("  oversize              "));
    EXPECT_THAT(ran.out, HasSubstr("no finding: the device served every liveness check"));
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
}

// Restarted by `mblab fuzz --restart`: the old one is gone before the new one opens the line.
TEST(FuzzSerial, ADeviceDeafAfterABadCrcIsFoundAndMinimised) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    TempDir dir;
    const auto device =
        std::filesystem::path(MBLAB_FRAGILE_DEVICE).parent_path() / "mblab_fragile_line_device";
    const auto pid_file = (dir.path() / "device.pid").string();
    const std::string restart = "pid=$(cat " + pid_file +
                                " 2>/dev/null); if [ -n \"$pid\" ]; then kill $pid; while kill -0 "
                                "$pid 2>/dev/null; do sleep 0.05; done; fi; rm -f " +
                                pid_file + "; " + device.string() + " " + pty.server_end() + " " +
                                pid_file + " >/dev/null 2>&1 </dev/null &";
    ASSERT_EQ(std::system(restart.c_str()), 0);
    for (int i = 0; i < 250 && file_text(pid_file).empty(); ++i)
        std::this_thread::sleep_for(20ms);
    ASSERT_FALSE(file_text(pid_file).empty());
    const auto reproducer = (dir.path() / "finding.hex").string();
    const auto ran =
        run_mblab({"fuzz", "rtu://" + pty.client_end() + "?baud=115200&data=8", "--cases", "300",
                   "--rate", "0", "--timeout", "300", "--check-every", "10", "--restart", restart,
                   "--reproducer", reproducer});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("frame-check: bad CRC to address 247 (the last unicast)"));
    EXPECT_THAT(ran.out, HasSubstr(" to 1 frame(s) in "));
    std::vector<std::string> steps;
    std::istringstream lines(file_text(reproducer));
    for (std::string line; std::getline(lines, line);) {
        if (!line.empty() && line[0] != '#') steps.push_back(line);
    }
    EXPECT_EQ(steps, std::vector<std::string>{"F7 03 00 00 00 01 91 9D"}) << ran.out;
    // Beside it, the frame as a capture Wireshark reads as Modbus RTU once User 0 is "mbrtu".
    std::string decoded;
    EXPECT_EQ(run_command({"tshark", "-o", kUser0IsModbusRtu, "-r", reproducer + ".pcapng", "-T",
                           "fields", "-e", "mbrtu.unit_id", "-e", "modbus.func_code"},
                          decoded),
              0)
        << decoded;
    EXPECT_THAT(decoded, HasSubstr("247\t3"));
    // The device fuzz restarted last may not have written its pid yet.
    kill_processes_naming(pid_file);
}

}  // namespace
}  // namespace mblab::test
