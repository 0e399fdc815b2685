// `mblab conform` on a serial line shows the frames that crossed the line: a failed case's
// evidence in the console and the JSON report is the RTU frame (address, PDU, CRC low byte first)
// or the ASCII text (':', hex, LRC, CR LF), never the MBAP notation the catalogue is written in;
// and `--pcap` on a line writes those frames, each packet commented with its case's id, as a
// capture of Modbus/TCP carries the ids too.
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "protocol/crc16.hpp"
#include "protocol/lrc.hpp"
#include "serial_test_support.hpp"
#include "support/hex.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

using namespace std::chrono_literals;

// tshark's option that decodes LINKTYPE_USER0, where mblab writes an RTU line's frames.
constexpr const char* kUser0IsModbusRtu =
    R"x(uat:user_dlts:"User 0 (DLT=147)","mbrtu","0","","0","")x";

// Two cases of a user suite: m.1 expects exception 02 to a plain read the device answers with
// data, so it fails with evidence; m.2 passes.
constexpr const char* kSuite = R"([suite]
name = "mine"

[[case]]
id = "m.1"
source = "me"
title = "read 1 register expecting 02"
request = "00 2A 00 00 {len} {unit} 03 00 00 00 01"
expect = "00 2A 00 00 {len} {unit} 83 02"

[[case]]
id = "m.2"
source = "me"
title = "read 2 registers"
request = "00 2B 00 00 {len} {unit} 03 00 00 00 02"
expect = "00 2B 00 00 {len} {unit} 03 04 XX XX XX XX"
)";

struct Run {
    Ran ran;
    nlohmann::json report;
};

// Runs the suite against `url` with the JSON report (and any `more` options).
Run run_suite(const TempDir& dir, const std::string& url, std::vector<std::string> more = {}) {
    const auto suite = (dir.path() / "mine.toml").string();
    std::ofstream(suite) << kSuite;
    const auto json = (dir.path() / "report.json").string();
    std::vector<std::string> args{"conform", url, "--suite", suite, "--json", json};
    args.insert(args.end(), more.begin(), more.end());
    Run run{run_mblab(args), {}};
    run.report = nlohmann::json::parse(file_text(json), nullptr, false);
    return run;
}

const nlohmann::json& evidence_of(const nlohmann::json& report) {
    return report["suites"][0]["cases"][0]["evidence"][0];
}

// An RTU frame whose last two bytes are its CRC, low byte first [SER 2.5.1.2].
bool crc_checks(const std::string& frame) {
    const auto bytes = hex(frame);
    return bytes.size() > 2 && protocol::crc16(bytes) == 0;
}

void shows_rtu_frames(const Run& run) {
    EXPECT_EQ(run.ran.status, 1) << run.ran.out << run.ran.err;
    ASSERT_FALSE(run.report.is_discarded()) << run.ran.out << run.ran.err;
    const auto& evidence = evidence_of(run.report);
    EXPECT_EQ(evidence["framing"], "RTU") << evidence;
    // Address 1, FC 03 of register 0, CRC 0x0A84 sent low byte first.
    EXPECT_EQ(evidence["sent"], "01 03 00 00 00 01 84 0A") << evidence;
    const std::string received = evidence["received"];
    EXPECT_EQ(received.rfind("01 03 02 ", 0), 0U) << received;
    EXPECT_EQ(received.size(), std::string("01 03 02 00 00 00 00").size()) << received;
    EXPECT_TRUE(crc_checks(received)) << received;
    // What was due: exception 02 and its CRC, 0xF1C0.
    EXPECT_EQ(evidence["expected"], "01 83 02 C0 F1") << evidence;
    EXPECT_EQ(evidence["differs"], nlohmann::json({1, 3, 4, 5, 6})) << evidence;
    EXPECT_THAT(run.ran.out, HasSubstr("           sent      01 03 00 00 00 01 84 0A\n"
                                       "           received  " +
                                       received +
                                       "\n"
                                       "           expected  01 83 02 C0 F1\n"
                                       "                        ^^    ^^ ^^ ^^ ^^\n"));
    // No MBAP header, which no line carries.
    EXPECT_THAT(run.ran.out, Not(HasSubstr("00 2A 00 00"))) << run.ran.out;
}

// `mblab serve` on one end of a pty pair in `scheme`, the suite run on the other end; stopped at
// the end of the test.
class ServedLine {
  public:
    explicit ServedLine(const std::string& scheme)
        : scheme_(scheme), serve_({MBLAB_BINARY, "serve", "--listen", url(pty_.server_end())}) {}
    ~ServedLine() {
        serve_.signal(SIGTERM);
        serve_.wait_exit(10s);
    }
    // "" once the device serves, else what failed.
    std::string started() {
        if (!pty_.ok()) return pty_.error();
        return serve_.read_stdout_line(10s) ? "" : "mblab serve did not start";
    }
    Run run(std::vector<std::string> more = {}) {
        return run_suite(dir_, url(pty_.client_end()), std::move(more));
    }
    std::string path(const char* name) const { return (dir_.path() / name).string(); }

  private:
    std::string url(const std::string& end) const {
        return scheme_ + "://" + end + "?baud=115200&data=8";
    }

    std::string scheme_;
    PtyPair pty_;
    ChildProcess serve_;
    TempDir dir_;
};

TEST(ConformLineEvidence, AnRtuCaseShowsTheFrameAsItCrossedTheLine) {
    ServedLine line("rtu");
    ASSERT_EQ(line.started(), "");
    shows_rtu_frames(line.run());
}

TEST(ConformLineEvidence, AnRtuOverTcpCaseShowsTheRtuFrame) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    TempDir dir;
    shows_rtu_frames(run_suite(dir, "rtu+tcp://127.0.0.1:" + std::to_string(device.port())));
}

TEST(ConformLineEvidence, AnAsciiCaseShowsTheFrameAsItsText) {
    ServedLine line("ascii");
    ASSERT_EQ(line.started(), "");
    const auto run = line.run();
    EXPECT_EQ(run.ran.status, 1) << run.ran.out << run.ran.err;
    ASSERT_FALSE(run.report.is_discarded()) << run.ran.out << run.ran.err;
    const auto& evidence = evidence_of(run.report);
    EXPECT_EQ(evidence["framing"], "ASCII") << evidence;
    // ':', address 01, FC 03 of register 0, LRC FB, CR LF written as \r\n.
    EXPECT_EQ(evidence["sent"], R"(:010300000001FB\r\n)") << evidence;
    const std::string received = evidence["received"];
    std::smatch parts;
    ASSERT_TRUE(std::regex_match(received, parts, std::regex(R"(:(010302[0-9A-F]{6})\\r\\n)")))
        << received;
    EXPECT_EQ(protocol::lrc(hex(parts[1].str())), 0) << received;
    EXPECT_EQ(evidence["expected"], R"(:0183027A\r\n)") << evidence;
    EXPECT_THAT(run.ran.out, HasSubstr("           sent      :010300000001FB\\r\\n\n"
                                       "           received  " +
                                       received +
                                       "\n"
                                       "           expected  :0183027A\\r\\n\n"
                                       "                        ^^  ^^^^^^\n"));
}

// tshark's fields of every packet in `pcap`, one line each; the comment field is frame.comment
// in the Wireshark of this machine, pkt_comment in older ones.
std::string tshark_fields(const std::string& pcap, std::vector<std::string> fields,
                          bool rtu = false) {
    for (const char* comment : {"frame.comment", "pkt_comment"}) {
        std::vector<std::string> argv{"tshark", "-r", pcap, "-T", "fields", "-e", comment};
        if (rtu) argv.insert(argv.begin() + 1, {"-o", kUser0IsModbusRtu});
        for (const auto& field : fields) {
            argv.push_back("-e");
            argv.push_back(field);
        }
        std::string out;
        if (run_command(argv, out) == 0 && out.find("case m.") != std::string::npos) return out;
    }
    return {};
}

TEST(ConformLineEvidence, APcapOfAnRtuLineHoldsItsFramesWithTheCaseIds) {
    ServedLine line("rtu");
    ASSERT_EQ(line.started(), "");
    const auto pcap = line.path("run.pcapng");
    const auto run = line.run({"--pcap", pcap});
    EXPECT_EQ(run.ran.status, 1) << run.ran.out << run.ran.err;
    const auto decoded =
        tshark_fields(pcap, {"frame.p2p_dir", "mbrtu.unit_id", "modbus.func_code"}, true);
    // Each case's request (outbound, 0) and answer (inbound, 1), decoded as Modbus RTU: unit 1,
    // FC 03, and commented with the case's id.
    for (const char* id : {"m.1", "m.2"}) {
        for (const char* direction : {"0", "1"}) {
            EXPECT_THAT(decoded,
                        HasSubstr(std::string("case ") + id + "\t" + direction + "\t1\t3\n"))
                << decoded;
        }
    }
}

TEST(ConformLineEvidence, APcapOfAnAsciiLineHoldsItsTextWithTheCaseIds) {
    ServedLine line("ascii");
    ASSERT_EQ(line.started(), "");
    const auto pcap = line.path("run.pcapng");
    line.run({"--pcap", pcap});
    // LINKTYPE_USER1, the frame's text as the packet's bytes.
    const auto packets = tshark_fields(pcap, {"frame.p2p_dir", "frame.encap_type", "data.data"});
    std::string text_hex;
    for (const char c : std::string(":010300000001FB\r\n"))
        text_hex += fmt::format("{:02x}", static_cast<unsigned char>(c));
    EXPECT_THAT(packets, HasSubstr("case m.1\t0\t46\t" + text_hex + "\n")) << packets;
    EXPECT_THAT(packets, HasSubstr("case m.2\t1\t46\t")) << packets;
}

TEST(ConformLineEvidence, APcapOfModbusTcpCarriesTheCaseIdsToo) {
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"});
    const auto banner = serve.read_stdout_line(10s);
    ASSERT_TRUE(banner.has_value());
    std::smatch port;
    ASSERT_TRUE(std::regex_search(*banner, port, std::regex(R"(tcp://127\.0\.0\.1:(\d+))")))
        << *banner;
    TempDir dir;
    const auto pcap = (dir.path() / "run.pcapng").string();
    const auto run = run_suite(dir, "tcp://127.0.0.1:" + port[1].str(), {"--pcap", pcap});
    EXPECT_EQ(run.ran.status, 1) << run.ran.out << run.ran.err;
    // The device's side is port 502 in the capture, where Wireshark decodes Modbus/TCP.
    const auto packets = tshark_fields(pcap, {"mbtcp.trans_id", "modbus.func_code"});
    EXPECT_THAT(packets, HasSubstr("case m.1\t42\t3\n")) << packets;
    EXPECT_THAT(packets, HasSubstr("case m.2\t43\t3\n")) << packets;
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
}

}  // namespace
}  // namespace mblab::test
