#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "device/reference_device.hpp"
#include "server/background_server.hpp"
#include "support/faulty_server.hpp"
#include "support/ports.hpp"
#include "support/rewriting_handler.hpp"
#include "support/temp_path.hpp"

// `mblab conform` as users run it: exit statuses, console lines, report files.
namespace mblab::conformance {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

using test::Ran;

std::string slurp(const std::string& path) {
    std::ifstream file(path);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

std::string temp(const std::string& name) {
    return test::temp_path(name);
}

// Runs build/mblab with `args`; every wait is bounded.
Ran mblab(std::vector<std::string> args) {
    args.insert(args.begin(), MBLAB_BINARY);
    return test::run_program(args, std::chrono::seconds(60));
}

TEST(ConformCli, TheReferenceDevicePassesEveryApplicableCase) {
    const std::string json = temp("reference.json");
    auto ran = mblab({"conform", "--json", json});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    auto report = nlohmann::json::parse(slurp(json));
    EXPECT_EQ(report["passed"], true);
    EXPECT_EQ(report["summary"]["failed"], 0);
    EXPECT_GT(report["summary"]["passed"], 100);
    EXPECT_EQ(report["dut"]["unit"], 1);
    EXPECT_EQ(report["dut"]["registers"], 65536);
    std::vector<std::string> suites;
    for (const auto& suite : report["suites"]) {
        suites.push_back(suite["name"]);
        for (const auto& c : suite["cases"]) {
            const std::string verdict = c["verdict"];
            if (c["id"] == "7.2") {
                // Ping depends on the machine's ICMP permissions, never on the device.
                EXPECT_TRUE(verdict == "PASS" || verdict == "NOT RUN") << c["reason"];
            } else if (suite["name"] == "policy-2.1") {
                EXPECT_EQ(verdict, "PASS") << c["id"] << ": " << c["reason"];
            } else if (suite["name"] == "serial" || suite["name"] == "sunspec") {
                // The serial line's rules do not apply to Modbus/TCP, nor SunSpec's to a device
                // without the SunS marker.
                EXPECT_EQ(verdict, "N/A") << c["id"] << ": " << c["reason"];
            } else {
                EXPECT_TRUE(verdict == "PASS" || verdict == "N/A")
                    << c["id"] << ": " << c["reason"];
            }
        }
    }
    EXPECT_EQ(suites, (std::vector<std::string>{"policy-2.1", "device-id", "diagnostics",
                                                "exceptions", "function-codes", "mbap", "security",
                                                "serial", "sunspec"}));
    EXPECT_THAT(
        ran.out,
        HasSubstr("  PASS     7.5.2   Multiple register test: the register sweep  (775 "
                  "reads of up to 125 registers over 65536 registers, one request at a time)\n"));
    EXPECT_THAT(ran.out, HasSubstr("\nSummary: "));
}

TEST(ConformCli, AnUnreachableTargetIsAUsageErrorOnOneLine) {
    const auto port = test::closed_port();
    auto ran = mblab({"conform", "tcp://127.0.0.1:" + std::to_string(port)});
    expect_failed(ran, 2,
                  "mblab conform: cannot connect to tcp://127.0.0.1:" + std::to_string(port) +
                      ": connection refused\n");
    EXPECT_EQ(ran.out, "");
}

// A device that takes connections and answers nothing: a wrong port behind a forwarder, a unit
// no gateway routes, a device in listen-only mode.
class MuteDevice {
  public:
    MuteDevice() {
        listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof address;
        if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), length) == 0 &&
            ::listen(listener_, 16) == 0 &&
            ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
            port_ = ntohs(address.sin_port);
        }
        thread_ = std::thread([this] {
            while (!stop_) {
                pollfd ready{listener_, POLLIN, 0};
                if (::poll(&ready, 1, 50) > 0)
                    held_.push_back(::accept(listener_, nullptr, nullptr));
            }
        });
    }
    ~MuteDevice() {
        stop_ = true;
        thread_.join();
        for (int fd : held_)
            ::close(fd);
        ::close(listener_);
    }
    std::uint16_t port() const { return port_; }

  private:
    int listener_ = -1;
    std::uint16_t port_ = 0;
    std::atomic<bool> stop_{false};
    std::vector<int> held_;
    std::thread thread_;
};

TEST(ConformCli, ADeviceThatAnswersNothingEndsTheRunAfterItsFirstCase) {
    MuteDevice device;
    ASSERT_NE(device.port(), 0);
    const auto json = temp("mute.json");
    auto ran = mblab({"conform", "tcp://127.0.0.1:" + std::to_string(device.port()), "--suite",
                      "exceptions", "--timeout", "300", "--json", json});
    EXPECT_EQ(ran.status, 2) << ran.out << ran.err;
    EXPECT_EQ(ran.err,
              "mblab conform: no answer on unit 1, 255 or 0 to 4 requests: check the port and "
              "--unit\n");
    EXPECT_THAT(ran.out, HasSubstr("units 255 and 0 did not answer either"));
    const auto report = nlohmann::json::parse(slurp(json));
    const auto& cases = report["suites"][0]["cases"];
    ASSERT_GT(cases.size(), 2U);
    EXPECT_EQ(cases[0]["verdict"], "FAIL");
    for (std::size_t i = 1; i < cases.size(); ++i) {
        EXPECT_EQ(cases[i]["verdict"], "NOT RUN") << cases[i];
        EXPECT_EQ(cases[i]["reason"], "the device answered nothing") << cases[i];
    }
    std::filesystem::remove(json);
}

TEST(ConformCli, AMalformedUserSuiteIsRefusedWithFileAndLine) {
    const std::string suite = temp("bad_suite.toml");
    std::ofstream(suite) << "[suite]\nname = \"mine\"\n\n[[case]]\nid = \"m.1\"\nsource = \"me\"\n"
                            "title = \"t\"\nrequest = \"00 00 00 00 {len} {unit} 03 00 00 00 ZZ\"\n"
                            "expect = \"00\"\n";
    auto ran = mblab({"conform", "--suite", suite});
    expect_failed(ran, 2,
                  "mblab conform: " + suite +
                      ":8: request: column 38: 'ZZ': expected hex bytes, XX, {placeholder} "
                      "or ...\n");
}

TEST(ConformCli, AUserSuiteRunsAgainstTheReferenceDevice) {
    const std::string suite = temp("good_suite.toml");
    std::ofstream(suite) << "[suite]\nname = \"mine\"\n\n[[case]]\nid = \"m.1\"\nsource = \"me\"\n"
                            "title = \"read 2 registers\"\n"
                            "request = \"00 2A 00 00 {len} {unit} 03 00 00 00 02\"\n"
                            "expect = \"00 2A 00 00 {len} {unit} 03 04 XX XX XX XX\"\n";
    auto ran = mblab({"conform", "--suite", suite});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("\nmine\n  PASS     m.1  read 2 registers\n"));
}

TEST(ConformCli, ListPrintsTheCatalogue) {
    auto ran = mblab({"conform", "--list", "--suite", "policy-2.1"});
    EXPECT_EQ(ran.status, 0);
    EXPECT_THAT(ran.out, HasSubstr("  9.1.3   Improper message length answers exception 03  (CTP "
                                   "9.1.3)\n"));
    EXPECT_THAT(ran.out, HasSubstr("  7.5.2   Multiple register test: the register sweep "
                                   "[register_sweep]  (CTP 7.5.2)\n"));
}

TEST(ConformCli, ASuiteThatCannotApplyIsOneLineAndTheSummarySaysWhatToDeclare) {
    auto loaded = device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
    ASSERT_TRUE(loaded.ok());
    server::BackgroundServer server(*loaded.value());
    auto port = server.start();
    ASSERT_TRUE(port.ok()) << port.error();
    const std::string html = test::temp_path("inapplicable.html");
    const std::string junit = test::temp_path("inapplicable.xml");
    auto ran = mblab({"conform", "tcp://127.0.0.1:" + std::to_string(*port), "--suite",
                      "function-codes", "--suite", "security", "--html", html, "--junit", junit});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    // Over tcp:// no security case can run: one line, not twelve.
    const std::string why = "a Modbus/TCP Security case: the device is not reached over mbaps://";
    EXPECT_NE(ran.out.find("  N/A      all 12 cases of security  (" + why), std::string::npos)
        << ran.out;
    EXPECT_EQ(ran.out.find("sec.1 "), std::string::npos) << ran.out;
    // The HTML report and JUnit say it the same way: one row, one <testcase>.
    const std::string page = slurp(html);
    EXPECT_THAT(page, HasSubstr("<td>all 12 cases of security</td><td>" + why));
    EXPECT_THAT(page, Not(HasSubstr("<td>sec.1</td>")));
    const std::string xml = slurp(junit);
    EXPECT_THAT(xml, HasSubstr("<testsuite name=\"security\" tests=\"1\" failures=\"0\" "
                               "errors=\"0\" skipped=\"1\""));
    EXPECT_THAT(xml, HasSubstr("name=\"all 12 cases of security\""));
    EXPECT_THAT(xml, HasSubstr("<skipped message=\"N/A: " + why));
    EXPECT_THAT(xml, Not(HasSubstr("sec.1 ")));
    // Nothing was declared: the N/A cases of function-codes are counted per missing key.
    EXPECT_NE(ran.out.find("N/A for want of a declaration, cases per DUT key: "), std::string::npos)
        << ran.out;
    EXPECT_NE(ran.out.find("coils ("), std::string::npos) << ran.out;
    EXPECT_NE(ran.out.find("registers ("), std::string::npos) << ran.out;
}

// A device built wrong: FC 01 of quantity 0 ([APP] 6.1: exception 03) is answered with 250
// bytes of data, 00 to 27 and then 5A.
TEST(ConformCli, DataWhereAnExceptionWasDueIsSaidInWordsWithTheLongFrameCompacted) {
    auto loaded = device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
    ASSERT_TRUE(loaded.ok());
    test::RewritingHandler wrong(
        *loaded.value(),
        [](std::span<const std::uint8_t> request) -> std::optional<std::vector<std::uint8_t>> {
            if (request.size() != 5 || request[0] != 0x01 || request[3] != 0 || request[4] != 0)
                return std::nullopt;
            std::vector<std::uint8_t> answer = {0x01, 250};
            for (std::uint8_t i = 0; i < 250; ++i)
                answer.push_back(i < 40 ? i : 0x5A);
            return answer;
        });
    server::BackgroundServer server(wrong);
    auto port = server.start();
    ASSERT_TRUE(port.ok()) << port.error();
    const std::string html = temp("data-for-exception.html");
    const std::string junit = temp("data-for-exception.xml");
    // COLUMNS cuts the evidence even though standard output is a pipe here.
    auto ran =
        test::run_program({"/usr/bin/env", "COLUMNS=80", MBLAB_BINARY, "conform",
                           "tcp://127.0.0.1:" + std::to_string(*port), "--suite", "function-codes",
                           "--case", "fc01.3", "--html", html, "--junit", junit},
                          std::chrono::seconds(60));
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    const std::string words =
        "answered with data where exception 03 (illegal data value) was expected";
    EXPECT_THAT(ran.out,
                HasSubstr("FAIL     fc01.3  Read coils, quantity 0 answers 03  (" + words + ")"));
    // The evidence is cut at 80 columns, the received bytes in three pieces, the run one cell.
    EXPECT_THAT(ran.out, HasSubstr("           received  00 03 00 00 00 FD 01 01 FA 00 01 02"));
    EXPECT_THAT(ran.out, HasSubstr(" 26 27 5A x210\n"));
    std::size_t pieces = 0;
    std::istringstream lines(ran.out);
    for (std::string line; std::getline(lines, line);) {
        if (!line.starts_with("           ")) continue;
        EXPECT_LE(line.size(), 80U) << line;
        pieces += line.starts_with("           received  ") ? 1 : 0;
    }
    EXPECT_EQ(pieces, 3U) << ran.out;
    const std::string page = slurp(html);
    EXPECT_THAT(page, HasSubstr("<td>" + words + "</td>"));
    EXPECT_THAT(page, HasSubstr("<mark class=\"diff\">5A x210</mark>"));
    const std::string xml = slurp(junit);
    EXPECT_THAT(xml, HasSubstr("<failure message=\"" + words + "\""));
    EXPECT_THAT(xml, HasSubstr(" 26 27 5A x210\n"));
}

class ConformCliFaultyTarget : public ::testing::Test {
  protected:
    void SetUp() override {
        auto loaded =
            device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
        ASSERT_TRUE(loaded.ok());
        device_ = std::move(loaded.value());
        server_ = std::make_unique<test::FaultyServer>(
            *device_, test::FaultRule{test::Fault::WrongTransactionId, 0x01});
        port_ = server_->start();
        ASSERT_NE(port_, 0);
    }
    std::string target() const { return "tcp://127.0.0.1:" + std::to_string(port_); }

    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<test::FaultyServer> server_;
    std::uint16_t port_ = 0;
};

TEST_F(ConformCliFaultyTarget, AFailureExitsOneAndShowsTheEvidenceInEveryReport) {
    const std::string json = temp("faulty.json");
    const std::string junit = temp("faulty.xml");
    const std::string pcap = temp("faulty.pcap");
    auto ran = mblab({"conform", target(), "--suite", "policy-2.1", "--unit", "1", "--registers",
                      "65536", "--object-messaging", "--alternate-encoding", "--json", json,
                      "--junit", junit, "--pcap", pcap});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out,
                HasSubstr("DUT: unit 1, 65536 registers, max read 125, object messaging: yes, "
                          "alternate encoding: yes (declared by flags)\n"));
    EXPECT_THAT(ran.out,
                HasSubstr("  FAIL     7.3.1   Function 0x01 read coils  (wrong transaction id)\n"
                          "           sent      00 00 00 00 00 06 01 01 00 00 00 01\n"
                          "           received  00 01 00 00 00 04 01 01 01 00\n"
                          "           expected  00 00 00 00 00 04 01 01 01 XX\n"
                          "                        ^^\n"));
    auto report = nlohmann::json::parse(slurp(json));
    // FC 01 also reads back the coil writes of 7.7.1 and 7.11.1.
    EXPECT_EQ(report["summary"]["failed"], 3);
    EXPECT_EQ(report["suites"][0]["cases"][1]["id"], "7.3.1");
    EXPECT_EQ(report["suites"][0]["cases"][1]["verdict"], "FAIL");
    const std::string xml = slurp(junit);
    EXPECT_THAT(xml, HasSubstr("<testsuite name=\"policy-2.1\" tests=\"18\" failures=\"3\""));
    EXPECT_THAT(xml, HasSubstr("<failure message=\"wrong transaction id\" type=\"FAIL\">"));
    ASSERT_TRUE(std::filesystem::exists(pcap));
    if (std::filesystem::exists("/usr/bin/tshark")) {
        // Every exchange dissects as Modbus/TCP: the requests and answers are all there, and
        // nothing is malformed.
        test::ChildProcess tshark({"/usr/bin/tshark", "-r", pcap, "-Y", "mbtcp", "-T", "fields",
                                   "-e", "_ws.malformed", "-e", "mbtcp.prot_id"});
        // One line per packet: the malformed flag (empty), then the protocol id of each PDU
        // in it ("0,0,0" when a pipelined write carried three requests).
        std::size_t pdus = 0;
        while (auto line = tshark.read_stdout_line(std::chrono::seconds(60))) {
            ASSERT_EQ(line->rfind("\t0", 0), 0U) << *line;
            for (std::size_t at = 1; at < line->size(); at += 2) {
                EXPECT_EQ(line->substr(at, 1), "0") << *line;
                ++pdus;
            }
        }
        EXPECT_EQ(tshark.wait_exit(std::chrono::seconds(60)), 0);
        EXPECT_GT(pdus, 1500U);  // about 806 requests and their answers
    }
}

TEST_F(ConformCliFaultyTarget, ADutFileDeclaresTheDevice) {
    const std::string dut = temp("dut.toml");
    std::ofstream(dut) << "unit = 1\nregisters = 65536\nmax_read = 125\n";
    auto ran = mblab({"conform", target(), "--suite", "policy-2.1", "--dut", dut});
    EXPECT_EQ(ran.status, 1);
    EXPECT_NE(ran.out.find("(declared by " + dut + ")\n"), std::string::npos) << ran.out;
    EXPECT_THAT(ran.out,
                HasSubstr("  N/A      7.13.1  Function 0x5B object messaging: class 1, instance "
                          "1, get attribute 1  (the DUT does not declare object_messaging)\n"));
}

}  // namespace
}  // namespace mblab::conformance
