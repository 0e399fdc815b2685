// `mblab fuzz --learn`: reconnaissance learned from captures that other programs wrote (dumpcap
// of mbpoll's traffic, editcap's conversion of mblab's own pcapng), and no probe sent.
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "robustness/learn.hpp"
#include "robustness/pcap_reader.hpp"
#include "support/hex.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;
using namespace std::chrono_literals;

bool installed(const char* path) {
    return ::access(path, X_OK) == 0;
}

// `mblab serve` on an ephemeral port, read from the line it prints.
class Serve {
  public:
    Serve() : child_({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"}) {
        const auto line = child_.read_stdout_line(10s).value_or("");
        std::smatch port;
        if (std::regex_search(line, port, std::regex(R"(tcp://127\.0\.0\.1:([0-9]+))")))
            port_ = static_cast<std::uint16_t>(std::stoi(port[1]));
    }
    ~Serve() {
        child_.signal(SIGTERM);
        child_.wait_exit(10s);
    }
    std::uint16_t port() const { return port_; }

  private:
    ChildProcess child_;
    std::uint16_t port_ = 0;
};

// dumpcap on the loopback interface, for one port. started() is false when it could not start
// capturing (not installed, no permission): the caller skips.
class Dumpcap {
  public:
    Dumpcap(std::uint16_t port, const fs::path& file)
        : file_(file),
          child_({"/usr/bin/dumpcap", "-q", "-i", "lo", "-f", "tcp port " + std::to_string(port),
                  "-w", file.string()}) {
        // dumpcap writes the section and interface blocks once it captures; the filter is in
        // place a moment after.
        for (int i = 0; i < 100 && !started_; ++i) {
            std::this_thread::sleep_for(100ms);
            std::error_code ignored;
            started_ = fs::file_size(file_, ignored) > 0 && !ignored;
        }
        if (started_) std::this_thread::sleep_for(500ms);
    }
    bool started() const { return started_; }
    // Stops the capture so that the file is whole; the last packets need a moment to arrive.
    std::string stop() {
        std::this_thread::sleep_for(500ms);
        child_.signal(SIGINT);
        child_.wait_exit(10s);
        return child_.drain_stderr();
    }

  private:
    fs::path file_;
    ChildProcess child_;
    bool started_ = false;
};

// The TCP payload bytes of each conversation of a capture, by tshark: "STREAM\tLEN" rows.
std::map<int, std::size_t> bytes_per_stream(const std::string& pcap) {
    const auto read = run_program(
        {"/usr/bin/tshark", "-r", pcap, "-T", "fields", "-e", "tcp.stream", "-e", "tcp.len"});
    std::map<int, std::size_t> out;
    std::istringstream rows(read.out);
    for (std::string row; std::getline(rows, row);) {
        const auto tab = row.find('\t');
        if (tab == std::string::npos || tab == 0 || tab + 1 == row.size()) continue;
        out[std::stoi(row.substr(0, tab))] += std::stoul(row.substr(tab + 1));
    }
    return out;
}

// mbpoll reads three tables of `mblab serve`, captured by dumpcap; fuzz learns from the capture,
// sends no probe, and the reference device has no finding.
TEST(FuzzLearn, LearnsFromMbpollTrafficCapturedByDumpcap) {
    if (!installed("/usr/bin/dumpcap") || !installed("/usr/bin/mbpoll") ||
        !installed("/usr/bin/tshark"))
        GTEST_SKIP() << "needs dumpcap, tshark and mbpoll";
    TempDir dir;
    Serve serve;
    ASSERT_NE(serve.port(), 0);
    const std::string port = std::to_string(serve.port());
    const auto capture = dir / "mbpoll.pcapng";
    {
        Dumpcap dumpcap(serve.port(), capture);
        if (!dumpcap.started())
            GTEST_SKIP() << "dumpcap cannot capture on lo here: " << dumpcap.stop();
        // mbpoll's references are 1-based: -r 101 is address 100.
        for (const std::vector<std::string>& table :
             {std::vector<std::string>{"-t", "4:hex", "-r", "101", "-c", "10"},
              {"-t", "3", "-r", "1", "-c", "4"},
              {"-t", "0", "-r", "1", "-c", "16"}}) {
            std::vector<std::string> argv = {
                "/usr/bin/mbpoll", "-m", "tcp", "-a", "1", "-1", "-p", port};
            argv.insert(argv.end(), table.begin(), table.end());
            argv.push_back("127.0.0.1");
            const auto polled = run_program(argv);
            ASSERT_EQ(polled.status, 0) << polled.out << polled.err;
        }
        dumpcap.stop();
    }

    const std::string run_capture = (dir / "fuzz.pcapng").string();
    const auto ran =
        run_mblab({"fuzz", "tcp://127.0.0.1:" + port, "--learn", capture.string(), "--cases", "50",
                   "--rate", "0", "--pcap", run_capture, "--json", (dir / "fuzz.json").string()});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(ran.out.find("reconnaissance (learned from " + capture.string() +
                           " (3 requests, 3 answers)): unit 1, serves 01 03 04;"),
              std::string::npos)
        << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("liveness check: FC 03 register 100; largest FC 03 read 10;"));
    EXPECT_THAT(ran.out, HasSubstr("answered at: coils 0-15; holding registers 100-109; input "
                                   "registers 0-3\n"));
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    const auto json = nlohmann::json::parse(file_text(dir / "fuzz.json"));
    EXPECT_EQ(json["recon"]["answered_ranges"]["holding_registers"],
              nlohmann::json::parse("[[100, 109]]"))
        << json.dump();

    // No probe: the first connection, which only showed the target reachable, carries no byte.
    // Without --learn the same place holds the probes, so this can fail.
    const auto learned = bytes_per_stream(run_capture);
    ASSERT_GT(learned.size(), 1U);
    EXPECT_EQ(learned.begin()->second, 0U);
    const std::string probed_capture = (dir / "probed.pcapng").string();
    const auto probed =
        run_mblab({"fuzz", "tcp://127.0.0.1:" + port, "--cases", "1", "--pcap", probed_capture});
    EXPECT_EQ(probed.status, 0) << probed.out << probed.err;
    const auto probes = bytes_per_stream(probed_capture);
    ASSERT_FALSE(probes.empty());
    EXPECT_GT(probes.begin()->second, 100U);
}

// mblab's own pcapng and editcap's classic pcap of it teach the same facts.
TEST(FuzzLearn, ConformPcapngAndItsClassicConversionLearnTheSame) {
    if (!installed("/usr/bin/editcap")) GTEST_SKIP() << "needs editcap (wireshark-common)";
    TempDir dir;
    const std::string pcapng = (dir / "conform.pcapng").string();
    const std::string pcap = (dir / "conform.pcap").string();
    const auto ran = run_mblab({"conform", "--suite", "mbap", "--pcap", pcapng});
    ASSERT_NE(ran.status, 2) << ran.out << ran.err;
    const auto converted = run_program({"/usr/bin/editcap", "-F", "pcap", pcapng, pcap});
    ASSERT_EQ(converted.status, 0) << converted.err;
    ASSERT_EQ(file_text(pcap).substr(0, 4), "\xD4\xC3\xB2\xA1");

    std::vector<robustness::Recon> learned;
    for (const auto& file : {pcapng, pcap}) {
        const std::string text = file_text(file);
        const auto capture = robustness::read_pcap(
            std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
        ASSERT_TRUE(capture) << capture.error();
        // mblab's captures show the device on port 502, whatever port it had.
        const auto recon = robustness::learn_recon(*capture, 502, "run");
        ASSERT_TRUE(recon) << recon.error();
        learned.push_back(*recon);
    }
    const auto& a = learned[0];
    const auto& b = learned[1];
    EXPECT_EQ(a.source, b.source);
    EXPECT_THAT(a.source, HasSubstr("learned from run ("));
    EXPECT_EQ(a.unit, b.unit);
    EXPECT_EQ(a.served, b.served);
    EXPECT_FALSE(a.served.empty());
    EXPECT_EQ(a.not_served, b.not_served);
    EXPECT_EQ(a.check_address, b.check_address);
    EXPECT_EQ(a.max_read, b.max_read);
    EXPECT_EQ(a.answers_unit_0, b.answers_unit_0);
    EXPECT_EQ(a.answers_unit_255, b.answers_unit_255);
    for (std::size_t t = 0; t < robustness::kTableCount; ++t) {
        const auto table = static_cast<robustness::Table>(t);
        EXPECT_EQ(a.ranges.of(table), b.ranges.of(table)) << robustness::table_name(table);
    }
    EXPECT_FALSE(a.ranges.of(robustness::Table::HoldingRegisters).empty());
}

// A classic pcap (raw IP) of one FC 03 read of 2 registers at 5 to `port`, and its answer.
std::string one_read_to(std::uint16_t port) {
    const auto p = fmt::format("{:04X}", port);
    const auto bytes =
        hex("D4C3B2A1 0200 0400 00000000 00000000 FFFF0000 65000000"
            "00000000 00000000 34000000 34000000"
            "4500 0034 0001 4000 4006 0000 7F000001 7F000001"
            "9C41" +
            p +
            "00000001 00000000 5018 FFFF 0000 0000"
            "0001 0000 0006 01 03 0005 0002"
            "00000000 00000000 35000000 35000000"
            "4500 0035 0002 4000 4006 0000 7F000001 7F000001" +
            p +
            "9C41 00000001 00000000 5018 FFFF 0000 0000"
            "0001 0000 0007 01 03 04 00000000");
    return std::string(bytes.begin(), bytes.end());
}

using FuzzLearnReference = ReferenceCliTest;

// --dut declares unit and max_read over what was learned; the rest stays learned.
TEST_F(FuzzLearnReference, TheDutFileStillDeclaresUnitAndMaxRead) {
    TempDir dir;
    std::ofstream(dir / "one.pcap", std::ios::binary) << one_read_to(port_);
    std::ofstream(dir / "dut.toml") << "unit = 1\nmax_read = 7\n";
    const auto learned = run_mblab(
        {"fuzz", target(), "--learn", (dir / "one.pcap").string(), "--cases", "20", "--rate", "0"});
    EXPECT_EQ(learned.status, 0) << learned.out << learned.err;
    EXPECT_THAT(learned.out, HasSubstr("FC 03 register 5; largest FC 03 read 2;"));
    const auto declared =
        run_mblab({"fuzz", target(), "--learn", (dir / "one.pcap").string(), "--dut",
                   (dir / "dut.toml").string(), "--cases", "20", "--rate", "0"});
    EXPECT_EQ(declared.status, 0) << declared.out << declared.err;
    EXPECT_NE(declared.out.find("(1 requests, 1 answers); unit and max_read declared by " +
                                (dir / "dut.toml").string() + "): unit 1, serves 03;"),
              std::string::npos)
        << declared.out;
    EXPECT_THAT(declared.out, HasSubstr("FC 03 register 5; largest FC 03 read 7;"));
    EXPECT_THAT(declared.out, HasSubstr("answered at: holding registers 5-6\n"));
}

// A capture with no FC 03 read answered, and a file that is no capture: exit 2, one line, before
// the target is even tried (port 1 is closed).
TEST(FuzzLearn, UnusableCapturesAreOneLine) {
    TempDir dir;
    // Classic pcap, raw IP: an FC 04 read to port 1 and its answer.
    std::ofstream(dir / "fc04.pcap", std::ios::binary) << [] {
        const auto bytes =
            hex("D4C3B2A1 0200 0400 00000000 00000000 FFFF0000 65000000"
                "00000000 00000000 34000000 34000000"
                "4500 0034 0001 4000 4006 0000 7F000001 7F000001"
                "9C41 0001 00000001 00000000 5018 FFFF 0000 0000"
                "0001 0000 0006 01 04 0000 0001"
                "00000000 00000000 33000000 33000000"
                "4500 0033 0002 4000 4006 0000 7F000001 7F000001"
                "0001 9C41 00000001 00000000 5018 FFFF 0000 0000"
                "0001 0000 0005 01 04 02 0000");
        return std::string(bytes.begin(), bytes.end());
    }();
    std::ofstream(dir / "notes.txt") << "hello\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {(dir / "fc04.pcap").string(),
         "mblab fuzz: " + (dir / "fc04.pcap").string() +
             ": no FC 03 read answered in 1 Modbus/TCP requests to port 1: nothing to check "
             "liveness with\n"},
        {(dir / "notes.txt").string(),
         "mblab fuzz: " + (dir / "notes.txt").string() +
             ": not a pcap or pcapng file: magic 68656C6C at offset 0\n"},
    };
    for (const auto& [file, error] : cases) {
        const auto ran = run_mblab({"fuzz", "tcp://127.0.0.1:1", "--learn", file, "--cases", "5"});
        EXPECT_EQ(ran.status, 2) << ran.out << ran.err;
        EXPECT_EQ(ran.err, error);
        EXPECT_TRUE(ran.out.empty()) << ran.out;
    }
}

}  // namespace
}  // namespace mblab::test
