// `mblab conform` over RTU and ASCII lines (pseudo-terminals) and RTU over TCP, against the
// reference device served by mblab's serial servers: every case that applies passes, the MBAP
// cases and ping are N/A with the reason, and a serial target refuses what it cannot do.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "serial_test_support.hpp"
#include "support/temp_path.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

nlohmann::json read_json(const std::string& path) {
    std::ifstream file(path);
    std::stringstream text;
    text << file.rdbuf();
    return nlohmann::json::parse(text.str(), nullptr, false);
}

// Verdict of every case, by id.
std::map<std::string, std::string> verdicts(const nlohmann::json& report) {
    std::map<std::string, std::string> out;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"])
            out[c["id"]] = c["verdict"];
    }
    return out;
}

// Runs the conformance suites against `url` and checks the verdicts a serial link must give.
void conforms_over(const std::string& url, const std::string& over) {
    const std::string json = temp_path("report.json");
    auto ran = run_mblab({"conform", url, "--registers", "65536", "--timeout", "3000", "--json",
                          json, "--suite", "policy-2.1", "--suite", "mbap", "--suite",
                          "diagnostics", "--suite", "device-id", "--suite", "exceptions"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto report = read_json(json);
    ASSERT_FALSE(report.is_discarded()) << ran.out << ran.err;
    EXPECT_EQ(report["summary"]["failed"], 0) << ran.out;
    EXPECT_EQ(report["dut"]["unit"], 1);  // the default address on a serial link
    const auto verdict = verdicts(report);
    for (const auto& [id, v] : verdict) {
        if (id.starts_with("mbap.") || id == "9.1.3") {
            EXPECT_EQ(v, "N/A") << id;
        } else if (id != "7.2" && id.starts_with("7.") && id != "7.13.1" && id != "7.13.2") {
            EXPECT_EQ(v, "PASS") << id;
        }
    }
    EXPECT_EQ(verdict.at("7.5.2"), "PASS");  // the whole register sweep, one read at a time
    EXPECT_EQ(verdict.at("9.1.2"), "PASS");
    EXPECT_EQ(verdict.at("9.1.4"), "PASS");
    // The MBAP suite cannot apply on a line: one line says so, not one per case.
    EXPECT_NE(ran.out.find("  N/A      all 10 cases of mbap  (a Modbus/TCP (MBAP) test; the device "
                           "is reached over " +
                           over + ")\n"),
              std::string::npos)
        << ran.out;
    EXPECT_EQ(ran.out.find("mbap.6"), std::string::npos) << ran.out;
}

std::string line_url(const std::string& scheme, const PtyPair& pty, unsigned baud) {
    return scheme + "://" + pty.client_end() + "?baud=" + std::to_string(baud) + "&data=8";
}

TEST(ConformSerial, ReferenceDevicePassesOverRtuAt9600) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 9600, false), "");
    conforms_over(line_url("rtu", line.pty(), 9600), "RTU");
}

TEST(ConformSerial, ReferenceDevicePassesOverAsciiAt115200) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "ascii", 115200, false), "");
    conforms_over(line_url("ascii", line.pty(), 115200), "ASCII");
}

TEST(ConformSerial, PingIsNotApplicableOnASerialLine) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 115200, false), "");
    auto ran = run_mblab({"conform", line_url("rtu", line.pty(), 115200), "--suite", "policy-2.1"});
    EXPECT_THAT(ran.out,
                HasSubstr("  N/A      7.2     Ping: 10 consecutive 32-byte echo requests are all "
                          "answered  (the device is on a serial line (RTU): it has no IP "
                          "address)\n"));
}

TEST(ConformSerial, TheRs485InstrumentAnswersItsDiagnosticsOverRtu) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("rs485-instrument", "rtu", 19200, false), "");
    const std::string dut = temp_path("rs485-instrument.toml");
    std::ofstream(dut) << "unit = 1\necho_max_words = 100\n";
    const std::string json = temp_path("rs485-instrument.json");
    auto ran = run_mblab({"conform", line_url("rtu", line.pty(), 19200), "--dut", dut, "--suite",
                          "diagnostics", "--suite", "device-id", "--json", json});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto verdict = verdicts(read_json(json));
    // FC 08 echo at the instrument's limit of 100 words, and exception 03 one word over it.
    EXPECT_EQ(verdict.at("diag.2"), "PASS") << ran.out;
    EXPECT_EQ(verdict.at("diag.3"), "PASS") << ran.out;
}

TEST(ConformSerial, AddressZeroIsRefusedOnASerialLine) {
    auto zero = run_mblab({"conform", "rtu:///dev/null?baud=9600", "--unit", "0"});
    EXPECT_EQ(zero.status, 2);
    EXPECT_EQ(zero.err,
              "mblab conform: unit 0 is not a serial device address: on "
              "rtu:///dev/null?baud=9600&parity=E&stop=1&data=8 a device answers at an address "
              "from 1 to 247 (0 is the broadcast); give it with --unit\n");
}

TEST(ConformRtuOverTcp, ReferenceDevicePasses) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    conforms_over("rtu+tcp://127.0.0.1:" + std::to_string(device.port()), "RTU over TCP");
}

}  // namespace
}  // namespace mblab::test
