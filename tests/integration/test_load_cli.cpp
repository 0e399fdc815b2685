#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "device/reference_device.hpp"
#include "load_cli_support.hpp"
#include "server/background_server.hpp"
#include "support/faulty_server.hpp"
#include "support/temp_path.hpp"

// `mblab load` against real servers on loopback: the verdict, the exit status, and counts
// that must equal what the devices' fault rules did.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using nlohmann::json;
using std::chrono::milliseconds;
using std::chrono::seconds;

// A port that refuses connections: bound, so nothing else takes it meanwhile, but not listening.
class RefusingPort {
  public:
    RefusingPort() : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t size = sizeof address;
        if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), size) == 0 &&
            ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &size) == 0) {
            port_ = ntohs(address.sin_port);
        }
    }
    ~RefusingPort() { ::close(fd_); }
    RefusingPort(const RefusingPort&) = delete;
    RefusingPort& operator=(const RefusingPort&) = delete;
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port_); }

  private:
    int fd_;
    std::uint16_t port_ = 0;
};

// Reads the URLs from `mblab serve`'s first line.
std::vector<std::string> served_urls(ChildProcess& serve) {
    std::vector<std::string> urls;
    auto banner = serve.read_stdout_line(seconds(10));
    if (!banner) return urls;
    const std::regex url(R"(tcp://127\.0\.0\.1:\d+)");
    for (std::sregex_iterator it(banner->begin(), banner->end(), url), end; it != end; ++it) {
        urls.push_back(it->str());
    }
    return urls;
}

// Reads the header up to the line of `last_node`: the run is under way after it.
std::string read_header(ChildProcess& child, const std::string& last_node) {
    std::string out;
    for (int lines = 0; lines < 20; ++lines) {
        auto line = child.read_stdout_line(seconds(10));
        if (!line) break;
        out += *line + "\n";
        if (line->find("node " + last_node) != std::string::npos) break;
    }
    return out;
}

TEST(LoadCli, ThreeServedReferenceDevicesPass) {
    ChildProcess serve({MBLAB_BINARY, "serve", "--devices", "3", "--listen", "tcp://127.0.0.1:0"});
    const auto targets = served_urls(serve);
    ASSERT_EQ(targets.size(), 3U);

    std::vector<std::string> args = targets;
    args.insert(args.end(), {"--duration", "2s", "--registers", "65536", "--connections", "6"});
    auto run = mblab_load("pass", args);
    serve.signal(SIGINT);
    EXPECT_EQ(serve.wait_exit(seconds(10)), 0);

    EXPECT_EQ(run.status, 0) << run.out << run.err;
    const json& report = run.report;
    EXPECT_EQ(report["verdict"], "PASS");
    EXPECT_EQ(report["passed"], true);
    EXPECT_EQ(report["interrupted"], false);
    EXPECT_EQ(report["duration_s"], 2.0);
    EXPECT_EQ(report["totals"]["failures"], 0);
    EXPECT_EQ(report["settings"]["suites"], json::array({"policy-2.1"}));
    EXPECT_EQ(report["settings"]["cases"].size(), 13U);
    ASSERT_EQ(report["nodes"].size(), 3U);
    for (std::size_t i = 0; i < 3; ++i) {
        const json& node = report["nodes"][i];
        EXPECT_EQ(node["target"], targets[i]);
        expect_clean(node);
        // Every protocol test ran on every node, alongside the generator's requests.
        for (const auto& exchange : node["exchanges"]) {
            EXPECT_GT(exchange["sent"].get<std::uint64_t>(), 0U) << exchange.dump();
            EXPECT_EQ(exchange["failed"], 0);
        }
        EXPECT_GT(node["latency_ms"]["count"].get<std::uint64_t>(), 0U);
        EXPECT_LE(node["latency_ms"]["p50"].get<double>(), node["latency_ms"]["p99"].get<double>());
        EXPECT_LE(node["latency_ms"]["p99_9"].get<double>(),
                  node["latency_ms"]["max"].get<double>());
    }
    EXPECT_THAT(run.out, HasSubstr("PASS: no failure on 3 nodes in 2 s under load (CTP 8.4)"));
    EXPECT_THAT(run.junit,
                HasSubstr("<testsuites name=\"mblab load 3 nodes\" tests=\"3\" failures=\"0\""));
    EXPECT_THAT(run.junit, HasSubstr("<testsuite name=\"load\" tests=\"3\" failures=\"0\""));
}

TEST(LoadCli, DroppedAnswersFailOnlyThatNodeWithExactCounts) {
    Device good1;
    Device faulty("[[unit.faults]]\naction = \"drop\"\nfunctions = [6]\nevery = 5\n");
    Device good2;
    auto run = mblab_load("drop", {good1.url(), faulty.url(), good2.url(), "--duration", "3s",
                                   "--registers", "65536", "--connections", "3", "--rate", "3000"});
    EXPECT_EQ(run.status, 1) << run.out << run.err;
    const json& report = run.report;
    EXPECT_EQ(report["verdict"], "FAIL");
    EXPECT_EQ(report["passed"], false);
    expect_clean(report["nodes"][0]);
    expect_clean(report["nodes"][2]);

    const json& node = report["nodes"][1];
    EXPECT_EQ(node["verdict"], "FAIL");
    // Only 7.8.1 sends FC 06 (its steps 1 and 3); the device drops every 5th, and each is one
    // timeout. A dropped write is still made, so the read-backs that follow pass.
    const auto fc06 = sent_with_function(node, 6);
    EXPECT_GE(fc06, 5U);
    EXPECT_EQ(failures(node, "timeout"), fc06 / 5);
    EXPECT_EQ(node["failures"]["total"], fc06 / 5);
    std::uint64_t write_failures = 0;
    for (const auto& exchange : node["exchanges"]) {
        const bool writes =
            exchange["name"] == "7.8.1 step 1" || exchange["name"] == "7.8.1 step 3";
        if (writes) write_failures += exchange["failed"].get<std::uint64_t>();
        if (!writes) {
            EXPECT_EQ(exchange["failed"], 0) << exchange;
        }
    }
    EXPECT_EQ(write_failures, fc06 / 5);
    const json& first = node["first_failure"];
    EXPECT_EQ(first["kind"], "timeout");
    const std::string step = first["exchange"];
    EXPECT_TRUE(step == "7.8.1 step 1" || step == "7.8.1 step 3") << step;
    EXPECT_EQ(first["reason"], "no answer from unit 1: timeout after 1000 ms");
    const std::string sent = first["evidence"]["sent"];
    ASSERT_EQ(sent.size(), 35U) << sent;
    // After our transaction id: the policy's write, or the read-back proof's second value.
    EXPECT_EQ(sent.substr(5, 24), " 00 00 00 06 01 06 00 10");
    EXPECT_TRUE(sent.substr(29) == " 12 34" || sent.substr(29) == " ED CB") << sent;
    EXPECT_EQ(first["evidence"]["expected"], sent);
    EXPECT_EQ(first["evidence"]["status"], "timeout");
    EXPECT_EQ(first["evidence"]["received"], "");

    EXPECT_NE(run.out.find("FAIL: 1 of 3 nodes failed (" + faulty.url() + ")"), std::string::npos)
        << run.out;
    EXPECT_NE(run.out.find("    sent      " + sent), std::string::npos) << run.out;
    EXPECT_THAT(run.junit, HasSubstr("tests=\"3\" failures=\"1\""));
}

TEST(LoadCli, EachKindOfFaultIsCountedOnItsNode) {
    Device good;
    Device faulty(
        "[[unit.faults]]\naction = \"close\"\nfunctions = [6]\nevery = 4\n"
        "[[unit.faults]]\naction = \"exception\"\nexception = 4\nfunctions = [5]\nevery = 3\n"
        "[[unit.faults]]\naction = \"garbage\"\ngarbage_bytes = 5\nfunctions = [7]\nevery = 2\n"
        "[[unit.faults]]\naction = \"delay\"\ndelay_ms = 1500\nfunctions = [15]\nevery = 3\n");
    auto run = mblab_load("kinds", {good.url(), faulty.url(), "--duration", "4s", "--registers",
                                    "65536", "--connections", "2", "--rate", "2000"});
    EXPECT_EQ(run.status, 1) << run.out << run.err;
    expect_clean(run.report["nodes"][0]);
    const json& node = run.report["nodes"][1];
    const auto fc05 = sent_with_function(node, 5);
    const auto fc06 = sent_with_function(node, 6);
    const auto fc07 = sent_with_function(node, 7);
    const auto fc15 = sent_with_function(node, 15);
    EXPECT_GE(fc06, 4U);
    EXPECT_GE(fc15, 3U);
    EXPECT_EQ(failures(node, "dropped"), fc06 / 4) << node["failures"];
    EXPECT_EQ(failures(node, "exception"), fc05 / 3) << node["failures"];
    // Random bytes mostly fail to decode; some decode as a response, just the wrong one. (Other
    // wrong answers come from read-backs after the writes the device refused or dropped.)
    for (const auto& exchange : node["exchanges"]) {
        if (exchange["name"] == "7.9.1") {
            EXPECT_EQ(exchange["failed"], fc07 / 2) << exchange;
        }
    }
    EXPECT_GE(failures(node, "malformed") + failures(node, "wrong_answer"), fc07 / 2)
        << node["failures"];
    // 1500 ms is over the 1000 ms timeout: each delayed answer is one timeout, and it comes
    // late rather than being taken for the next request's.
    EXPECT_EQ(failures(node, "timeout"), fc15 / 3) << node["failures"];
    EXPECT_EQ(failures(node, "refused"), 0U);
    EXPECT_LE(node["late_answers"].get<std::uint64_t>(), fc15 / 3);
    EXPECT_NE(run.out.find("FAIL: 1 of 2 nodes failed (" + faulty.url() + ")"), std::string::npos)
        << run.out;
}

TEST(LoadCli, ADeviceThatGoesAwayIsReportedNotCrashedOn) {
    Device stays;
    // A server of its own process, so that stopping it really closes its port (a child of
    // this process would hold the in-process servers' listening sockets open).
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"});
    const auto leaves = served_urls(serve);
    ASSERT_EQ(leaves.size(), 1U);
    ChildProcess child(
        load_argv("leave", {stays.url(), leaves[0], "--duration", "3s", "--registers", "65536",
                            "--connections", "2", "--rate", "2000"}));
    std::string out = read_header(child, leaves[0]);
    std::this_thread::sleep_for(milliseconds(800));
    serve.signal(SIGINT);
    EXPECT_EQ(serve.wait_exit(seconds(10)), 0);
    auto run = finish(child, "leave", out);

    EXPECT_EQ(run.status, 1) << run.out << run.err;
    expect_clean(run.report["nodes"][0]);
    const json& node = run.report["nodes"][1];
    EXPECT_EQ(node["verdict"], "FAIL");
    EXPECT_GE(failures(node, "dropped"), 1U) << node["failures"];
    EXPECT_GE(failures(node, "refused"), 1U) << node["failures"];
    EXPECT_EQ(failures(node, "timeout"), 0U) << node["failures"];
    EXPECT_EQ(node["first_failure"]["kind"], "dropped");
    EXPECT_EQ(node["first_failure"]["evidence"]["status"], "closed");
    EXPECT_NE(run.out.find("FAIL: 1 of 2 nodes failed (" + leaves[0] + ")"), std::string::npos)
        << run.out;
}

// A device of tests/support that breaks its answers one way, on a connection at a time.
struct FaultyDevice {
    explicit FaultyDevice(FaultRule rule) {
        auto loaded =
            device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
        EXPECT_TRUE(loaded.ok());
        device = std::move(loaded.value());
        server = std::make_unique<FaultyServer>(*device, rule);
        port = server->start();
    }
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port); }

    std::unique_ptr<device::ReferenceDevice> device;
    std::unique_ptr<FaultyServer> server;
    std::uint16_t port = 0;
};

TEST(LoadCli, AnAnswerWithAnotherTransactionIdIsAWrongAnswer) {
    FaultyDevice faulty({Fault::WrongTransactionId, 0x06});
    auto run = mblab_load("tid", {faulty.url(), "--duration", "1s", "--connections", "0", "--case",
                                  "7.3.1", "--case", "7.8.1"});
    EXPECT_EQ(run.status, 1) << run.out << run.err;
    const json& node = run.report["nodes"][0];
    const auto fc06 = sent_with_function(node, 6);
    EXPECT_GT(fc06, 0U);
    EXPECT_EQ(failures(node, "wrong_answer"), fc06);
    EXPECT_EQ(node["failures"]["total"], fc06);  // each counted once, not again as a timeout
    EXPECT_EQ(node["late_answers"], 0);
    EXPECT_EQ(node["first_failure"]["reason"], "wrong transaction id");
    EXPECT_EQ(node["first_failure"]["exchange"], "7.8.1 step 1");
}

// --case takes the patterns mblab conform takes, and brings the cases a chosen one depends on.
TEST(LoadCli, CasePatternsChooseAsConformChooses) {
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"});
    const auto targets = served_urls(serve);
    ASSERT_EQ(targets.size(), 1U);
    // 7.13.2 (FC 5B, alternate encoding) depends on 7.5.1 and is itself N/A for this DUT.
    auto run = mblab_load("glob", {targets[0], "--duration", "1s", "--connections", "0", "--case",
                                   "7.3.?", "--case", "7.13.2"});
    serve.signal(SIGINT);
    EXPECT_EQ(serve.wait_exit(seconds(10)), 0);
    EXPECT_EQ(run.status, 0) << run.out << run.err;
    EXPECT_EQ(run.report["settings"]["cases"], json::array({"7.3.1", "7.5.1"}));
    EXPECT_THAT(run.out, HasSubstr("not in the loop: 7.13.2 (N/A: the DUT does not declare "
                                   "alternate_encoding)"));
}

TEST(LoadCli, AnswersOutOfOrderAreMatchedByTransactionId) {
    FaultyDevice reordering({Fault::ReorderAnswers, 0});
    auto run =
        mblab_load("reorder", {reordering.url(), "--no-tests", "--connections", "1", "--pipeline",
                               "4", "--mix", "fc3:1,fc3:2,fc1:9,fc4:3", "--duration", "1s"});
    EXPECT_EQ(run.status, 0) << run.out << run.err;
    expect_clean(run.report["nodes"][0]);
}

TEST(LoadCli, CtrlCEndsTheRunWithASummary) {
    Device device;
    const std::string html = temp("interrupt.html");
    ChildProcess child(
        load_argv("interrupt", {device.url(), "--duration", "1h", "--connections", "2", "--rate",
                                "1000", "--registers", "65536", "--html", html}));
    std::string out = read_header(child, device.url());
    std::this_thread::sleep_for(milliseconds(500));
    child.signal(SIGINT);
    auto run = finish(child, "interrupt", out);

    EXPECT_EQ(run.status, 1) << run.out << run.err;  // not a pass: the hour did not run
    EXPECT_EQ(run.report["verdict"], "INCOMPLETE");
    EXPECT_EQ(run.report["interrupted"], true);
    EXPECT_LT(run.report["elapsed_s"].get<double>(), 3600.0);
    const json& node = run.report["nodes"][0];
    EXPECT_EQ(node["verdict"], "INCOMPLETE");
    EXPECT_EQ(node["failures"]["total"], 0);
    EXPECT_GT(node["requests"].get<std::uint64_t>(), 0U);
    EXPECT_THAT(run.out, HasSubstr("INCOMPLETE: stopped after"));
    EXPECT_THAT(run.junit,
                HasSubstr("<skipped message=\"NOT RUN: stopped before the duration ended"));
    EXPECT_THAT(slurp(html), HasSubstr("INCOMPLETE: interrupted after"));
}

TEST(LoadCli, GeneratorAloneWithPipelinedRequests) {
    Device device;
    auto run =
        mblab_load("generator", {device.url(), "--no-tests", "--connections", "4", "--pipeline",
                                 "8", "--mix", "fc3:10=1,fc16:5@100=1", "--duration", "1s"});
    EXPECT_EQ(run.status, 0) << run.out << run.err;
    EXPECT_EQ(run.report["settings"]["tests"], false);
    EXPECT_EQ(run.report["settings"]["pipeline"], 8);
    EXPECT_EQ(run.report["settings"]["mix"], "fc3:10=1,fc16:5@100=1");
    const json& node = run.report["nodes"][0];
    expect_clean(node);
    ASSERT_EQ(node["exchanges"].size(), 2U);
    EXPECT_EQ(node["exchanges"][0]["name"], "fc3:10");
    EXPECT_EQ(node["exchanges"][1]["name"], "fc16:5@100");
    EXPECT_GT(node["exchanges"][0]["sent"].get<std::uint64_t>(), 0U);
    EXPECT_GT(node["exchanges"][1]["sent"].get<std::uint64_t>(), 0U);
    EXPECT_THAT(run.out, HasSubstr("protocol tests: none"));
}

TEST(LoadCli, UnreachableNodeIsASetupError) {
    const RefusingPort port;
    const std::string url = port.url();
    auto run = mblab_load("unreachable", {url, "--duration", "1s"});
    expect_failed(run, 2, "mblab load: cannot connect to " + url + ": connection refused\n");
    EXPECT_EQ(run.out, "");
    EXPECT_TRUE(run.report.is_null());
}

TEST(LoadCli, BadArgumentsAreUsageErrors) {
    Device device;
    auto mix = mblab_load("usage", {device.url(), "--mix", "fc9:1"});
    expect_failed(
        mix, 2,
        "mblab load: --mix entry 'fc9:1': function 9 is not one the generator sends (1, 2, "
        "3, 4, 5, 6, 15, 16) (expected fcCODE[:QUANTITY][@ADDRESS][=WEIGHT], e.g. "
        "fc3:125=70)\n");
    auto duration = mblab_load("usage", {device.url(), "--duration", "5x"});
    expect_failed(duration, 2,
                  "mblab load: --duration: '5x' is not a duration: give e.g. 250ms, 1s, 1.5s or "
                  "2m (a number alone is seconds) (run 'mblab load --help' for usage)\n");
    auto unknown_case = mblab_load("usage", {device.url(), "--case", "7.99"});
    expect_failed(unknown_case, 2,
                  "mblab load: --case '7.99' matches no case of the selected suites (policy-2.1); "
                  "conform --list shows the case ids\n");
    auto twice = mblab_load("usage", {device.url(), device.url()});
    EXPECT_EQ(twice.status, 2);
    EXPECT_EQ(twice.err,
              "mblab load: " + device.url() + " is given twice; each node is one device\n");
    auto nothing = mblab_load("usage", {device.url(), "--no-tests", "--connections", "0"});
    EXPECT_EQ(nothing.status, 2);
    EXPECT_THAT(nothing.err, HasSubstr("nothing to run"));
}

}  // namespace
}  // namespace mblab::test
