// The real `mblab serve` process: the line it prints, its exit statuses, SIGTERM, and --state
// persistence across a restart.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "blocking_client.hpp"
#include "child_process.hpp"
#include "scripted_handler.hpp"
#include "security/pki.hpp"
#include "serve_process.hpp"
#include "server/background_server.hpp"
#include "server_fixture.hpp"
#include "support/hex.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;
using namespace std::chrono_literals;

TEST(ServeCommand, PrintsWhereItListensAndExitsZeroOnSigterm) {
    Serve serve({"--listen", "tcp://127.0.0.1:0"});
    ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
    EXPECT_TRUE(std::regex_match(serve.line(),
                                 std::regex("mblab serve: reference profile on "
                                            "tcp://127\\.0\\.0\\.1:[0-9]+, unit 1 \\(0 and 255 "
                                            "answer as 1; other unit ids are not answered\\); "
                                            "stop with Ctrl-C")))
        << serve.line();
    auto client = serve.connect();
    EXPECT_EQ(client.transact("00 01 00 00 00 06 01 03 00 00 00 01"),
              "00 01 00 00 00 05 01 03 02 53 45");
    EXPECT_EQ(serve.terminate(), 0);
}

// A single device reached directly [TCPG 4.4.1.2]: its own unit, and 0 and 255 as itself. Any
// other unit id gets no answer (a gateway would answer 0B), so a client's wrong --unit shows.
TEST(ServeCommand, AnswersItsUnitAnd0And255AndLeavesOtherUnitIdsUnanswered) {
    Serve serve({"--listen", "tcp://127.0.0.1:0"});
    ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
    auto client = serve.connect();
    for (const std::string unit : {"01", "00", "FF"}) {
        EXPECT_EQ(client.transact("00 01 00 00 00 06 " + unit + " 03 00 00 00 01"),
                  "00 01 00 00 00 05 " + unit + " 03 02 53 45")
            << unit;
    }
    for (const std::string unit : {"09", "02", "F7", "FE"})
        EXPECT_EQ(client.transact("00 02 00 00 00 06 " + unit + " 03 00 00 00 01", 300ms), "");
    // Unanswered, not out of step: the connection serves the next request.
    EXPECT_EQ(client.transact("00 03 00 00 00 06 01 03 00 00 00 01"),
              "00 03 00 00 00 05 01 03 02 53 45");
    const std::string target = tcp_target(serve.ports().front());
    const Ran nine =
        run_mblab({"read", target, "holding", "0", "--unit", "9", "--timeout", "300ms"});
    EXPECT_NE(nine.status, 0) << nine.out;
    for (const char* unit : {"1", "0", "255"}) {
        const Ran ran =
            run_mblab({"read", target, "holding", "0", "--unit", unit, "--timeout", "300ms"});
        EXPECT_EQ(ran.status, 0) << unit << ": " << ran.err;
    }
    EXPECT_EQ(serve.terminate(), 0);
}

// A profile of several units answers each of them; its other unit ids follow its
// unmatched_unit (multi-unit: exception 0A, as a gateway).
TEST(ServeCommand, AProfileOfSeveralUnitsAnswersEachOfThem) {
    Serve serve({"multi-unit", "--listen", "tcp://127.0.0.1:0"});
    ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
    EXPECT_THAT(serve.line(), HasSubstr("units 1,2,17 (0 and 255 answer as 1; other unit ids are "
                                        "answered exception 0A, as by a gateway)"));
    auto client = serve.connect();
    for (const std::string unit : {"01", "02", "11", "00", "FF"}) {
        // Each unit has a map of its own: register 0 may be data or exception 02, never 0A.
        const auto answer = client.transact("00 01 00 00 00 06 " + unit + " 03 00 00 00 01");
        ASSERT_GE(answer.size(), 20U) << unit;
        EXPECT_EQ(answer.substr(0, 20), "00 01 00 00 00 0" + answer.substr(16, 1) + " " + unit)
            << unit << ": " << answer;
        EXPECT_EQ(answer.find(" 83 0A"), std::string::npos) << unit;
    }
    EXPECT_EQ(client.transact("00 02 00 00 00 06 09 03 00 00 00 01"), "00 02 00 00 00 03 09 83 0A");
    EXPECT_EQ(serve.terminate(), 0);
}

TEST(ServeCommand, RunsSeveralDevicesOnTheirOwnPorts) {
    Serve serve({"--listen", "tcp://127.0.0.1:0", "--devices", "3"});
    ASSERT_EQ(serve.ports().size(), 3U) << serve.line();
    for (std::size_t i = 0; i < 3; ++i) {
        auto client = serve.connect(i);
        // Each device has its own data: a write to one is not seen by the others.
        if (i == 0) {
            EXPECT_EQ(client.transact("00 01 00 00 00 06 01 06 00 40 00 07"),
                      "00 01 00 00 00 06 01 06 00 40 00 07");
        } else {
            EXPECT_EQ(client.transact("00 01 00 00 00 06 01 03 00 40 00 01"),
                      "00 01 00 00 00 05 01 03 02 00 00");
        }
    }
    EXPECT_EQ(serve.terminate(), 0);
}

// With --devices K, each device keeps its own state file: lab.json -> lab-1.json, lab-2.json.
TEST(ServeCommand, SeveralDevicesKeepTheirOwnState) {
    TempDir dir;
    const auto state = (dir / "lab.json").string();
    const std::vector<std::string> args = {
        "--listen", "tcp://127.0.0.1:0", "--devices", "2", "--state",
        state,      "--save-interval",   "0"};
    {
        Serve serve(args);
        ASSERT_EQ(serve.ports().size(), 2U) << serve.line();
        auto first = serve.connect(0);
        auto second = serve.connect(1);
        EXPECT_EQ(first.transact("00 01 00 00 00 06 01 06 00 20 01 01"),
                  "00 01 00 00 00 06 01 06 00 20 01 01");
        EXPECT_EQ(second.transact("00 01 00 00 00 06 01 06 00 20 02 02"),
                  "00 01 00 00 00 06 01 06 00 20 02 02");
        EXPECT_EQ(serve.terminate(), 0);
    }
    EXPECT_FALSE(fs::exists(state));
    ASSERT_TRUE(fs::exists(dir / "lab-1.json"));
    ASSERT_TRUE(fs::exists(dir / "lab-2.json"));
    Serve again(args);
    ASSERT_EQ(again.ports().size(), 2U) << again.line();
    EXPECT_EQ(again.connect(0).transact("00 02 00 00 00 06 01 03 00 20 00 01"),
              "00 02 00 00 00 05 01 03 02 01 01");
    EXPECT_EQ(again.connect(1).transact("00 02 00 00 00 06 01 03 00 20 00 01"),
              "00 02 00 00 00 05 01 03 02 02 02");
    EXPECT_EQ(again.terminate(), 0);
}

TEST(ServeCommand, KeepsAcknowledgedWritesAcrossASigtermRestart) {
    TempDir dir;
    auto state = (dir / "device.json").string();
    {
        Serve serve({"--listen", "tcp://127.0.0.1:0", "--state", state, "--save-interval", "0"});
        ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
        auto client = serve.connect();
        expect_exchanges(
            client,
            {
                {"00 01 00 00 00 06 01 06 00 20 BE EF", "00 01 00 00 00 06 01 06 00 20 BE EF"},
                {"00 02 00 00 00 06 01 05 00 09 FF 00", "00 02 00 00 00 06 01 05 00 09 FF 00"},
                {"00 03 00 00 00 0B 01 10 00 30 00 02 04 11 11 22 22",
                 "00 03 00 00 00 06 01 10 00 30 00 02"},
            });
        EXPECT_EQ(serve.terminate(), 0);
    }
    ASSERT_TRUE(fs::exists(state));
    EXPECT_FALSE(fs::exists(state + ".tmp"));
    Serve again({"--listen", "tcp://127.0.0.1:0", "--state", state});
    ASSERT_EQ(again.ports().size(), 1U) << again.line();
    auto client = again.connect();
    expect_exchanges(
        client,
        {
            {"00 04 00 00 00 06 01 03 00 20 00 01", "00 04 00 00 00 05 01 03 02 BE EF"},
            {"00 05 00 00 00 06 01 01 00 08 00 02", "00 05 00 00 00 04 01 01 01 02"},
            {"00 06 00 00 00 06 01 03 00 30 00 02", "00 06 00 00 00 07 01 03 04 11 11 22 22"},
        });
    EXPECT_EQ(again.terminate(), 0);
}

// The ```LANG block that follows `after` in `text`; empty when there is none.
std::string fenced_block(const std::string& text, const std::string& after,
                         const std::string& lang) {
    auto at = text.find(after);
    if (at == std::string::npos) return {};
    auto open = text.find("```" + lang + "\n", at);
    if (open == std::string::npos) return {};
    open += 4 + lang.size();
    auto close = text.find("```", open);
    return close == std::string::npos ? std::string() : text.substr(open, close - open);
}

// docs/profiles.md's state file example is what `--state` writes for the profile and the writes
// the text gives, byte for byte.
TEST(ServeCommand, StateFileExampleOfTheProfileDocIsWhatServeWrites) {
    const std::string doc = file_text(fs::path(MBLAB_SOURCE_DIR) / "docs" / "profiles.md");
    const std::string profile = fenced_block(doc, "## State files", "toml");
    const std::string expected = fenced_block(doc, "## State files", "json");
    ASSERT_FALSE(profile.empty());
    ASSERT_FALSE(expected.empty());
    TempDir dir;
    std::ofstream(dir / "tiny.toml") << profile;
    auto state = (dir / "state.json").string();
    {
        Serve serve({(dir / "tiny.toml").string(), "--listen", "tcp://127.0.0.1:0", "--state",
                     state, "--save-interval", "0"});
        ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
        const std::string port = std::to_string(serve.ports()[0]);
        const std::string target = "tcp://127.0.0.1:" + port;
        EXPECT_EQ(run_mblab({"write", target, "--unit", "3", "registers", "10", "1", "2"}).status,
                  0);
        EXPECT_EQ(run_mblab({"write", target, "--unit", "3", "coil", "1", "1"}).status, 0);
        EXPECT_EQ(serve.terminate(), 0);
    }
    EXPECT_EQ(file_text(state), expected);
}

// The periodic save alone (the process is killed, so there is no save on exit).
TEST(ServeCommand, SavesStatePeriodically) {
    TempDir dir;
    auto state = (dir / "device.json").string();
    {
        Serve serve({"--listen", "tcp://127.0.0.1:0", "--state", state, "--save-interval", "0.1"});
        ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
        auto client = serve.connect();
        EXPECT_EQ(client.transact("00 01 00 00 00 06 01 06 00 21 0B 0B"),
                  "00 01 00 00 00 06 01 06 00 21 0B 0B");
        // Wait (at most 10 s) for a save that holds the write: the file exists after the first.
        for (int i = 0; i < 1000 && !fs::exists(state); ++i)
            std::this_thread::sleep_for(10ms);
        std::this_thread::sleep_for(300ms);  // a save that started after the write
        serve.process().signal(SIGKILL);
        serve.process().wait_exit(10s);
    }
    Serve again({"--listen", "tcp://127.0.0.1:0", "--state", state});
    auto client = again.connect();
    EXPECT_EQ(client.transact("00 02 00 00 00 06 01 03 00 21 00 01"),
              "00 02 00 00 00 05 01 03 02 0B 0B");
    EXPECT_EQ(again.terminate(), 0);
}

// --stats prints a line a second and a last one at exit, with the totals.
TEST(ServeCommand, StatsLineCountsRequestsAndExceptions) {
    Serve serve({"--listen", "tcp://127.0.0.1:0", "--stats"});
    ASSERT_EQ(serve.ports().size(), 1U) << serve.line();
    auto client = serve.connect();
    expect_exchanges(
        client, {
                    {"00 01 00 00 00 06 01 03 00 00 00 01", "00 01 00 00 00 05 01 03 02 53 45"},
                    {"00 02 00 00 00 02 01 25", "00 02 00 00 00 03 01 A5 01"},
                });
    EXPECT_EQ(serve.terminate(), 0);
    auto text = serve.process().drain_stderr();
    auto last = text.substr(text.rfind('\n', text.size() - 2) + 1);
    EXPECT_TRUE(std::regex_match(
        last, std::regex("mblab serve: [01] connections, [0-9]+ req/s, "
                         "[0-9]+ exc/s; total 2 requests, 1 exceptions, "
                         "0 busy, 0 refused, 0 evicted, 0 closed for a slow frame\n")))
        << text;
}

// [tls] in a profile names the files of `serve --listen mbaps://`, relative to the profile; an
// option on the command line wins over the profile's file.
TEST(ServeCommand, MbapsTakesItsFilesFromTheProfilesTlsTable) {
    TempDir dir;
    const auto made = security::make_lab_pki(dir / "pki", {});
    ASSERT_TRUE(made) << made.error();
    {
        std::ofstream profile(dir / "lab.toml");
        profile << file_text(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml")
                << "\n[tls]\ncert = \"pki/server.pem\"\nkey = \"pki/server.key\"\n"
                   "ca = \"pki/ca.pem\"\n";
    }
    Serve serve({"--listen", "mbaps://127.0.0.1:0", (dir / "lab.toml").string()});
    std::smatch port;
    ASSERT_TRUE(
        std::regex_search(serve.line(), port, std::regex("mbaps://127\\.0\\.0\\.1:([0-9]+)")))
        << serve.line();
    const auto pki = (dir / "pki").string();
    auto read = run_mblab({"read", "mbaps://127.0.0.1:" + port[1].str(), "holding", "16", "1",
                           "--cert", pki + "/client-Operator.pem", "--key",
                           pki + "/client-Operator.key", "--ca", pki + "/ca.pem"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(serve.terminate(), 0);

    auto missing = run_mblab({"serve", "--listen", "mbaps://127.0.0.1:0", "--key",
                              pki + "/nothing.key", (dir / "lab.toml").string()});
    expect_failed(missing, 2,
                  "mblab serve: --key " + pki + "/nothing.key: No such file or directory\n");
}

TEST(ServeCommand, BadUrlIsOneLineAndExitTwo) {
    expect_failed(run_failing({"--listen", "udp://127.0.0.1:502"}), 2,
                  "mblab serve: bad address 'udp://127.0.0.1:502': only tcp:// is served over TCP "
                  "(expected tcp://HOST:PORT, e.g. tcp://127.0.0.1:502)\n");
}

TEST(ServeCommand, PortInUseIsOneLineAndExitTwo) {
    ScriptedHandler handler;
    server::BackgroundServer occupant(handler);
    auto port = occupant.start();
    ASSERT_TRUE(port) << port.error();
    expect_failed(run_failing({"--listen", "tcp://127.0.0.1:" + std::to_string(*port)}), 2,
                  "mblab serve: cannot listen on 127.0.0.1:" + std::to_string(*port) +
                      ": Address already in use\n");
}

TEST(ServeCommand, UnknownProfileIsOneLineAndExitTwo) {
    expect_one_line(run_failing({"no-such-profile"}),
                    "mblab serve: no profile file or shipped profile named 'no-such-profile'");
}

TEST(ServeCommand, BrokenProfileIsOneLineAndExitTwo) {
    TempDir dir;
    auto profile = dir / "broken.toml";
    std::ofstream(profile) << "name = \"broken\"\n[[unit]]\nid = 300\n";
    expect_one_line(run_failing({profile.string(), "--listen", "tcp://127.0.0.1:0"}),
                    "mblab serve: " + profile.string());
}

TEST(ServeCommand, CorruptStateFileIsOneLineAndExitTwo) {
    TempDir dir;
    auto state = dir / "device.json";
    std::ofstream(state) << "this is not a state file";
    expect_one_line(run_failing({"--listen", "tcp://127.0.0.1:0", "--state", state.string()}),
                    "mblab serve: state file " + state.string());
}

TEST(ServeCommand, BadAllowEntryIsOneLineAndExitTwo) {
    expect_failed(
        run_failing({"--listen", "tcp://127.0.0.1:0", "--allow", "10.0.0.0/33"}), 2,
        "mblab serve: bad --allow entry '10.0.0.0/33' (expected an IP address or a network "
        "such as 192.168.1.0/24)\n");
}

}  // namespace
}  // namespace mblab::test
