// `mblab fuzz` as a user runs it: devices that die on one input each are found and minimised to
// the killing frame; robust devices, unusual ones included, get no finding.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "child_process.hpp"
#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "fuzz_fragile.hpp"
#include "support/faulty_server.hpp"
#include "support/ports.hpp"
#include "support/sanitizer.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

TEST_F(FuzzFragile, ACrashOnProtocolIdIsMinimisedToTheOneFrame) {
    start("protocol-id");
    // Ten cases between checks: the frames since the last good check are minimised to one.
    auto ran = fuzz({"--cases", "100", "--check-every", "10", "--restart", restart_, "--junit",
                     (dir_ / "fuzz.xml").string()});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("FINDING: the device refuses connections"));
    EXPECT_THAT(ran.out, HasSubstr("frame(s)"));
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    // Transaction id, then a protocol id that is not 0.
    EXPECT_NE(steps[0].substr(6, 5), "00 00") << steps[0];
    const auto junit = file_text(dir_ / "fuzz.xml");
    const auto failure = junit.find("<failure");
    ASSERT_NE(failure, std::string::npos) << junit;
    EXPECT_NE(junit.rfind("name=\"protocol-id\"", failure), std::string::npos);
    EXPECT_NE(junit.find(steps[0], failure), std::string::npos) << junit;
    if (std::ifstream("/usr/bin/xmllint")) {
        const auto lint = run_program({"/usr/bin/xmllint", "--noout", "--schema",
                                       std::string(MBLAB_SOURCE_DIR) + "/tests/junit-10.xsd",
                                       (dir_ / "fuzz.xml").string()});
        EXPECT_EQ(lint.status, 0) << lint.err;
    }

    // The reproducer as a capture too: its frame in a segment of its own.
    std::string frame;
    for (std::size_t at = 0; at < steps[0].size(); at += 3)
        frame.push_back(static_cast<char>(std::stoi(steps[0].substr(at, 2), nullptr, 16)));
    EXPECT_NE(file_text(dir_ / "finding.hex.pcapng").find(frame), std::string::npos);

    // The reproducer replays: against a restarted device it kills it again.
    restart();
    auto replayed =
        run_mblab({"fuzz", tcp_target(port_), "--replay", (dir_ / "finding.hex").string()});
    EXPECT_EQ(replayed.status, 1) << replayed.out << replayed.err;
    EXPECT_THAT(replayed.out, HasSubstr("replayed 1 frame(s): the device refuses connections"));
}

TEST_F(FuzzFragile, AHangOnMbapLengthOneIsFound) {
    start("length-one");
    const auto ran = expect_fuzz({"--cases", "100", "--timeout", "300ms", "--restart", restart_}, 1,
                                 "does not answer the known-good read");
    EXPECT_THAT(ran.out, HasSubstr("mbap-length: MBAP length 1 for 6 bytes"));
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    EXPECT_EQ(steps[0].substr(12, 5), "00 01") << steps[0];
}

TEST_F(FuzzFragile, SilenceAfterAByteCountMismatchIsFound) {
    start("byte-count");
    auto ran = fuzz({"--cases", "200", "--timeout", "300ms", "--check-every", "5", "--restart",
                     restart_, "--allow-writes"});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    EXPECT_EQ(steps[0].substr(21, 2), "10") << steps[0];
}

TEST_F(FuzzFragile, WithoutRestartTheFindingIsNotMinimised) {
    start("protocol-id");
    const auto ran = expect_fuzz({"--cases", "100", "--check-every", "3"}, 1,
                                 "could not minimise (no --restart)");
    EXPECT_EQ(reproducer().size(), 3U) << ran.out;
}

// Writes are withheld without a writable range: the byte-count device is never sent FC 10.
TEST_F(FuzzFragile, NoWriteLeavesWithoutPermission) {
    start("byte-count");
    expect_fuzz({"--cases", "150", "--timeout", "300ms", "--check-every", "10"}, 0,
                "withheld (writes not allowed)");
}

// Inside a declared writable range the writes go out, and the byte-count mismatch is found.
TEST_F(FuzzFragile, WritesGoOutInsideTheWritableRange) {
    start("byte-count");
    expect_fuzz({"--cases", "150", "--timeout", "300ms", "--writable", "0:10"}, 1,
                "byte-count: FC 0x10 byte count 0 for 1 registers");
}

TEST_F(FuzzFragile, ADeviceThatClosesOnGarbageIsRobust) {
    start("closes-garbage");
    expect_fuzz({"--cases", "200"}, 0, "no finding");
}

TEST_F(FuzzFragile, ALateDeviceIsRobust) {
    start("late");
    expect_fuzz({"--cases", "40", "--check-every", "5", "--timeout", "1s"}, 0, "no finding");
}

// A device that writes its answers with blocking sends: one client that never reads its answers
// fills the socket, and the device's one loop waits on it, serving nobody.
TEST_F(FuzzFragile, ASlowReaderThatStallsEveryoneIsFound) {
    start("blocking-send");
    const auto ran =
        expect_fuzz({"--cases", "100", "--timeout", "300ms", "--restart", restart_}, 1,
                    "slow-reader: 1 connection(s), 40000 FC 03 reads of 125 each, answers "
                    "never read");
    EXPECT_THAT(ran.out, HasSubstr("does not answer the known-good read"));
    // The one step, marked as never read: the replay leaves it unread too and stalls the device.
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    EXPECT_TRUE(steps[0].ends_with(" unread")) << steps[0].substr(0, 80);
    restart();
    auto replayed = fuzz({"--replay", (dir_ / "finding.hex").string(), "--timeout", "300ms"});
    EXPECT_EQ(replayed.status, 1) << replayed.out << replayed.err;
}

// Acknowledges every FC 06 but, given more than 8 requests at once, keeps none of them: the
// flood's ledger reads the register back and finds an acknowledged write gone.
TEST_F(FuzzFragile, AnAcknowledgedWriteThatIsLostIsFound) {
    start("loses-writes");
    const auto ran =
        expect_fuzz({"--cases", "120", "--timeout", "300ms", "--writable", "0:10"}, 1,
                    "FINDING: the device lost an acknowledged write: register 0 reads ");
    EXPECT_THAT(ran.out,
                HasSubstr("flood: 20000 requests streamed, FC 06 of 1..10000 to register 0"));
    EXPECT_THAT(ran.out, HasSubstr("not minimised: a lost write is judged over the whole flood"));
}

// The same device without writes allowed: the flood's writes are withheld and nothing is lost.
TEST_F(FuzzFragile, WithoutAWritableRangeTheFloodWritesNothing) {
    start("loses-writes");
    expect_fuzz({"--cases", "120", "--timeout", "300ms"}, 0,
                "flood                 1 run, 1 withheld");
}

// 64 slots, and a newcomer evicts only a connection stuck in a partial frame: idle connections
// held open lock everyone out, where [TCPG 4.2.1.1] has the oldest idle one closed.
TEST_F(FuzzFragile, ADeviceThatLocksNewcomersOutBehindIdleConnectionsIsFound) {
    start("few-slots");
    const auto ran = expect_fuzz({"--cases", "200", "--timeout", "300ms"}, 1,
                                 "connections, a request on each, held open");
    EXPECT_THAT(ran.out, HasSubstr("closes a fresh connection before answering"));
}

using FuzzReference = ReferenceCliTest;

TEST_F(FuzzReference, TheReferenceDeviceHasNoFinding) {
    TempDir dir;
    auto ran = run_mblab({"fuzz", target(), "--cases", "300", "--rate", "0", "--json",
                          (dir / "fuzz.json").string(), "--pcap", (dir / "fuzz.pcapng").string()});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    const auto json = file_text(dir / "fuzz.json");
    EXPECT_THAT(json, HasSubstr("\"verdict\": \"no finding\""));
    EXPECT_THAT(json, HasSubstr("\"cases\": 300"));
    EXPECT_FALSE(file_text(dir / "fuzz.pcapng").empty());
}

// The pairwise class in its turn among the others: its first rows reach the device, writes aimed
// outside --writable are withheld, and the reference device survives them.
TEST_F(FuzzReference, PairwiseCasesRunWithoutAFinding) {
    TempDir dir;
    auto ran = run_mblab({"fuzz", target(), "--cases", "400", "--rate", "0", "--writable", "0:10",
                          "--json", (dir / "fuzz.json").string()});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    EXPECT_THAT(ran.out, HasSubstr("  pairwise"));
    const auto json = nlohmann::json::parse(file_text(dir / "fuzz.json"));
    EXPECT_EQ(json["verdict"], "no finding");
    const nlohmann::json* pairwise = nullptr;
    for (const auto& row : json["classes"]) {
        if (row["class"] == "pairwise") pairwise = &row;
    }
    ASSERT_NE(pairwise, nullptr) << json.dump(2);
    // A function at a time in turn: at least the first row of each of the 12 served functions
    // with a layout (FC 01 to 06, 08, 0F, 10, 16, 17, 2B).
    EXPECT_GE((*pairwise)["run"].get<std::size_t>(), 12U) << json.dump(2);
    EXPECT_GT((*pairwise)["withheld"].get<std::size_t>(), 0U);
    EXPECT_FALSE((*pairwise)["finding"].get<bool>());
}

// A DUT file's unit and max_read replace the probed ones; --duration alone bounds the run.
TEST_F(FuzzReference, DeclaredFactsAndATimeBudget) {
    TempDir dir;
    std::ofstream(dir / "dut.toml") << "unit = 1\nmax_read = 10\n";
    auto ran = run_mblab({"fuzz", target(), "--cases", "0", "--duration", "1s", "--dut",
                          (dir / "dut.toml").string()});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(ran.out.find("reconnaissance (" + (dir / "dut.toml").string() + "): unit 1"),
              std::string::npos)
        << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("largest FC 03 read 10;"));
    EXPECT_THAT(ran.out, HasSubstr("(time budget)"));
}

// One connection at a time, served in turn: the connection kept open across cases holds the
// device, so the check drops it rather than call the device dead.
TEST(FuzzOneAtATime, ADeviceServingOneConnectionAtATimeIsNotDead) {
    auto loaded = device::load_profile(device::default_profile_path());
    ASSERT_TRUE(loaded) << loaded.error();
    FaultyServer server(**loaded, {});
    const auto port = server.start();
    ASSERT_NE(port, 0);
    // The first round up to unit-id: what comes next (a partial header left hanging) does stall
    // a device that serves one connection at a time, and that is a finding.
    auto ran =
        run_mblab({"fuzz", tcp_target(port), "--cases", "11", "--rate", "0", "--timeout", "300ms"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("the device serves one connection at a time"));
}

// Our own server as a process, every class against it and the resource cases with it: two
// thousand connections held, slow readers, floods, half-open connections. No finding, memory
// bounded, and the flood's last acknowledged write read back.
TEST(FuzzOwnServer, ServeSurvivesEveryClassAndTheResourceCases) {
    using namespace std::chrono_literals;
    TempDir dir;
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"});
    std::smatch match;
    const auto line = serve.read_stdout_line(10s).value_or("");
    ASSERT_TRUE(std::regex_search(line, match, std::regex("tcp://127\\.0\\.0\\.1:[0-9]+"))) << line;
    const std::string target = match[0];
    const auto json_path = (dir / "fuzz.json").string();
    // Every fixed case and some mutations; register 100 on is writable in the reference
    // profile. Long enough that the run is read with a longer patience than run_mblab's.
    ChildProcess fuzz({MBLAB_BINARY, "fuzz", target, "--cases", "1500", "--rate", "0", "--writable",
                       "100:10", "--device-pid", std::to_string(serve.pid()), "--json", json_path});
    Ran ran;
    while (auto out = fuzz.read_stdout_line(180s))
        ran.out += *out + "\n";
    ran.status = fuzz.wait_exit(10s).value_or(-1);
    ran.err = fuzz.drain_stderr();
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    const auto report = nlohmann::json::parse(file_text(dir / "fuzz.json"));
    for (const auto& row : report["classes"]) {
        const std::string name = row["class"];
        if (!row["not_applicable"].get<std::string>().empty()) continue;
        EXPECT_GT(row["run"].get<int>(), 0) << name;
        EXPECT_FALSE(row["finding"].get<bool>()) << name;
    }
    auto run_of = [&](std::string_view name) {
        for (const auto& row : report["classes"]) {
            if (row["class"] == name) return row["run"].get<int>();
        }
        return -1;
    };
    EXPECT_EQ(run_of("slow-reader"), 2);
    EXPECT_EQ(run_of("flood"), 2);
    EXPECT_EQ(run_of("many-connections"), 5);
    if (::geteuid() == 0) {
        EXPECT_EQ(run_of("half-open"), 2);
    }
    EXPECT_EQ(report["ledger"]["floods_read_back"], 1);
    EXPECT_EQ(report["ledger"]["acknowledged_writes"], 10000);
    // Megabytes of answers went unread (10 MB on one connection alone) and two thousand
    // connections came at once: the server grows by less than one slow reader's answers.
    // AddressSanitizer keeps freed memory in quarantine (up to 256 MiB), so there the bound is
    // looser; the plain build grows by under a MiB.
    constexpr std::size_t kGrowthKb = kAddressSanitizer ? 64U * 1024U : 8U * 1024U;
    const auto start = report["device_memory_kb"]["start"].get<std::size_t>();
    const auto peak = report["device_memory_kb"]["peak"].get<std::size_t>();
    EXPECT_GT(start, 0U);
    EXPECT_GE(peak, start);
    EXPECT_LT(peak - start, kGrowthKb) << ran.out;
    EXPECT_NE(ran.out.find("device memory (pid " + std::to_string(serve.pid()) + ")"),
              std::string::npos)
        << ran.out;
}

// On a terminal, a progress line names each case as it starts with the cases out of the total and
// the time left, rewritten in place, and is cleared before the summary; on a pipe there is none.
TEST_F(FuzzReference, TheProgressLineShowsOnATerminalOnly) {
    TempDir dir;
    const std::string command =
        std::string(MBLAB_BINARY) + " fuzz " + target() + " --cases 3 --rate 0 2>&1";
    auto ran = run_program({"/usr/bin/script", "-qec", command, "/dev/null"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("\r\033[Kcase 1/3, about "));
    EXPECT_THAT(ran.out, HasSubstr(" left: protocol-id: protocol id 0x0001"));
    EXPECT_THAT(ran.out, HasSubstr("\r\033[Kcase 3/3, about 0s left: "));
    EXPECT_THAT(ran.out, HasSubstr("\r\033[K3 cases in"));
    auto piped = run_mblab({"fuzz", target(), "--cases", "3", "--rate", "0"});
    EXPECT_EQ(piped.status, 0) << piped.out << piped.err;
    EXPECT_EQ(piped.err.find("case 1"), std::string::npos) << piped.err;
    EXPECT_EQ(piped.out.find("\033[K"), std::string::npos) << piped.out;
}

// Each usage error is one line, exit status 2.
TEST(FuzzUsage, BadUsageIsOneLine) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"tcp://127.0.0.1:1", "--writable", "x"},
         "mblab fuzz: --writable 'x' is not START:COUNT of holding registers (e.g. 100:10)\n"},
        {{"tcp://127.0.0.1:1", "--cases", "0"},
         "mblab fuzz: no budget: give --cases N or --duration D (it is pointed at devices)\n"},
        {{"rtu:///dev/null", "--unit", "0"},
         "mblab fuzz: unit 0 is broadcast, never answered on a serial line: give the device's "
         "address (--unit)\n"},
    };
    for (const auto& [args, error] : cases) {
        std::vector<std::string> argv = {"fuzz"};
        argv.insert(argv.end(), args.begin(), args.end());
        const auto ran = run_mblab(argv);
        EXPECT_EQ(ran.status, 2) << args.front() << ran.err;
        EXPECT_EQ(ran.err.substr(0, error.size()), error);
        EXPECT_EQ(ran.err.find('\n'), ran.err.size() - 1) << ran.err;
    }
}

}  // namespace
}  // namespace mblab::test
