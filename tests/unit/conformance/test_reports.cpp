#include <gtest/gtest.h>
#include <pcap/pcap.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "conformance/capture.hpp"
#include "conformance/evidence_text.hpp"
#include "conformance/reports.hpp"
#include "support/hex.hpp"
#include "support/temp_path.hpp"

namespace mblab::conformance {
namespace {

using test::hex;

Exchange failed_read() {
    Exchange exchange;
    exchange.sent = hex("00 00 00 00 00 06 01 01 00 00 00 01");
    exchange.status = client::ReceiveStatus::Frame;
    exchange.received = hex("00 01 00 00 00 04 01 01 01 00");
    exchange.expected = "00 00 00 00 00 04 01 01 01 XX";
    exchange.match =
        match(ResolvedPattern{Pattern::parse("00 00 00 00 00 04 01 01 01 XX")->tokens()},
              exchange.received);
    return exchange;
}

RunResult sample_run() {
    RunResult run;
    run.target = "tcp://127.0.0.1:1502";
    run.dut.unit = 1;
    run.dut.registers = 100;
    run.dut.declared_by = "flags";
    run.elapsed = std::chrono::microseconds(250000);
    run.requests = 12;
    SuiteResult suite{"policy-2.1", "Policy", "policy-2.1.toml", {}};
    suite.cases.push_back({"7.3.1", "CTP 7.3.1", "Read coils",
                           Outcome{Verdict::Fail, "wrong transaction id", {failed_read()}},
                           std::chrono::microseconds(1500), 1});
    suite.cases.push_back({"7.5.1", "CTP 7.5.1", "Read <registers> & \"more\"",
                           Outcome{Verdict::Pass, "", {}}, std::chrono::microseconds(500), 1});
    suite.cases.push_back(
        {"7.13.1", "CTP 7.13.1", "Object messaging",
         Outcome{Verdict::NotApplicable, "the DUT does not declare object_messaging", {}},
         std::chrono::microseconds(0), 0});
    suite.cases.push_back({"7.2", "CTP 7.2", "Ping", Outcome{Verdict::NotRun, "no ICMP socket", {}},
                           std::chrono::microseconds(0), 0});
    run.suites.push_back(suite);
    return run;
}

Provenance sample_provenance() {
    Provenance provenance;
    provenance.version = "0.1.0";
    provenance.commit = "abc1234";
    provenance.started = "2026-11-24T08:54:31Z";
    provenance.finished = "2026-11-24T08:54:33Z";
    provenance.command_line = {"mblab",  "conform", "tcp://127.0.0.1:1502", "--registers", "100",
                               "--case", "7.5.*"};
    provenance.declared_by = "flags";
    provenance.declarations = {{"unit", std::uint32_t{1}, "defaults"},
                               {"registers", std::uint32_t{100}, "flag --registers"},
                               {"object_messaging", false, "defaults"},
                               {"pki", std::string("lab & <pki>"), "dut.toml"}};
    provenance.device = {true, "mblab", "MBLAB-REF", "0.1.0", ""};
    return provenance;
}

TEST(Provenance, TimesAreUtcIso8601) {
    EXPECT_EQ(iso8601_utc(std::chrono::system_clock::time_point(std::chrono::seconds(0))),
              "1970-01-01T00:00:00Z");
    EXPECT_EQ(iso8601_utc(std::chrono::system_clock::time_point(std::chrono::seconds(1795510471))),
              "2026-11-24T08:54:31Z");
}

TEST(Provenance, TheCommandLineIsQuotedAsAShellWouldNeedIt) {
    EXPECT_EQ(
        shell_words({"mblab", "conform", "--case", "7.5.*", "--dut", "my dut.toml", "it's", ""}),
        "mblab conform --case '7.5.*' --dut 'my dut.toml' 'it'\\''s' ''");
}

TEST(Provenance, DeclarationsNameEveryKeyWithAValueAndItsSource) {
    Dut dut;
    dut.registers = 100;
    dut.security.write_role = "Operator";
    auto declarations = declarations_of(dut, [](std::string_view key) {
        return key == "registers" ? std::string("flag --registers") : std::string("defaults");
    });
    std::vector<std::string> keys;
    for (const auto& declaration : declarations)
        keys.push_back(declaration.key + "=" + value_text(declaration) + " (" + declaration.source +
                       ")");
    EXPECT_EQ(keys,
              (std::vector<std::string>{
                  "unit=1 (defaults)", "registers=100 (flag --registers)",
                  "max_read=125 (defaults)", "object_messaging=false (defaults)",
                  "alternate_encoding=false (defaults)", "fifo_count_writable=false (defaults)",
                  "write_role=Operator (defaults)", "null_role_granted=false (defaults)"}));
}

TEST(EvidenceText, MarksTheDifferingBytes) {
    EXPECT_EQ(
        evidence_lines(failed_read()),
        (std::vector<std::string>{"sent      00 00 00 00 00 06 01 01 00 00 00 01",
                                  "received  00 01 00 00 00 04 01 01 01 00",
                                  "expected  00 00 00 00 00 04 01 01 01 XX", "             ^^"}));
}

TEST(EvidenceText, SaysTimeoutWhenNothingCame) {
    Exchange exchange;
    exchange.sent = hex("00 00 00 00 00 02 01 07");
    exchange.status = client::ReceiveStatus::Timeout;
    exchange.waited = std::chrono::milliseconds(1000);
    exchange.expected = "00 00 00 00 00 03 01 07 XX";
    exchange.match = match(ResolvedPattern{Pattern::parse(exchange.expected)->tokens()}, {});
    auto lines = evidence_lines(exchange);
    ASSERT_EQ(lines.size(), 3U);
    EXPECT_EQ(lines[1], "received  timeout after 1000 ms");
    EXPECT_EQ(lines[2], "expected  00 00 00 00 00 03 01 07 XX");
}

TEST(JsonReport, CarriesVerdictsEvidenceAndSummary) {
    auto report = nlohmann::json::parse(json_report(sample_run(), sample_provenance()));
    EXPECT_EQ(report["target"], "tcp://127.0.0.1:1502");
    EXPECT_EQ(report["passed"], false);
    EXPECT_EQ(report["requests"], 12);
    EXPECT_EQ(report["summary"]["passed"], 1);
    EXPECT_EQ(report["summary"]["failed"], 1);
    EXPECT_EQ(report["summary"]["not_applicable"], 1);
    EXPECT_EQ(report["summary"]["not_run"], 1);
    EXPECT_EQ(report["dut"]["registers"], 100);
    EXPECT_FALSE(report["dut"].contains("coils"));
    const auto& failed = report["suites"][0]["cases"][0];
    EXPECT_EQ(failed["id"], "7.3.1");
    EXPECT_EQ(failed["verdict"], "FAIL");
    EXPECT_EQ(failed["evidence"][0]["received"], "00 01 00 00 00 04 01 01 01 00");
    EXPECT_EQ(failed["evidence"][0]["status"], "frame");
    EXPECT_EQ(failed["evidence"][0]["differs"], nlohmann::json::array({1}));
    EXPECT_EQ(report["suites"][0]["cases"][2]["verdict"], "N/A");
    EXPECT_EQ(report["suites"][0]["cases"][3]["verdict"], "NOT RUN");
}

TEST(JsonReport, CarriesTheProvenance) {
    auto report = nlohmann::json::parse(json_report(sample_run(), sample_provenance()));
    const auto& provenance = report["provenance"];
    EXPECT_EQ(provenance["mblab_version"], "0.1.0");
    EXPECT_EQ(provenance["git_commit"], "abc1234");
    EXPECT_EQ(provenance["started"], "2026-11-24T08:54:31Z");
    EXPECT_EQ(provenance["finished"], "2026-11-24T08:54:33Z");
    EXPECT_EQ(provenance["command_line"],
              nlohmann::json::array({"mblab", "conform", "tcp://127.0.0.1:1502", "--registers",
                                     "100", "--case", "7.5.*"}));
    EXPECT_EQ(provenance["declared_by"], "flags");
    // Values keep their JSON types.
    EXPECT_EQ(
        provenance["declarations"][1],
        (nlohmann::json{{"key", "registers"}, {"value", 100}, {"source", "flag --registers"}}));
    EXPECT_EQ(provenance["declarations"][2]["value"], false);
    EXPECT_EQ(provenance["device_identity"], (nlohmann::json{{"status", "answered"},
                                                             {"vendor_name", "mblab"},
                                                             {"product_code", "MBLAB-REF"},
                                                             {"revision", "0.1.0"}}));
}

TEST(JsonReport, SaysWhyTheDeviceDidNotIdentifyItself) {
    Provenance provenance = sample_provenance();
    provenance.device = {false, "", "", "", "exception 01 (illegal function)"};
    auto report = nlohmann::json::parse(json_report(sample_run(), provenance));
    EXPECT_EQ(report["provenance"]["device_identity"],
              (nlohmann::json{{"status", "not answered"},
                              {"reason", "exception 01 (illegal function)"}}));
}

TEST(JunitReport, IsTheExpectedDocument) {
    EXPECT_EQ(junit_report(sample_run(), sample_provenance()),
              R"(<?xml version="1.0" encoding="UTF-8"?>
<testsuites name="mblab conform tcp://127.0.0.1:1502" tests="4" failures="1" errors="0" time="0.002000">
  <testsuite name="policy-2.1" tests="4" failures="1" errors="0" skipped="2" time="0.002000">
    <properties>
      <property name="mblab.version" value="0.1.0"/>
      <property name="mblab.commit" value="abc1234"/>
      <property name="run.started" value="2026-11-24T08:54:31Z"/>
      <property name="run.finished" value="2026-11-24T08:54:33Z"/>
      <property name="run.command_line" value="mblab conform tcp://127.0.0.1:1502 --registers 100 --case &apos;7.5.*&apos;"/>
      <property name="dut.declared_by" value="flags"/>
      <property name="dut.unit" value="1"/>
      <property name="dut.unit.source" value="defaults"/>
      <property name="dut.registers" value="100"/>
      <property name="dut.registers.source" value="flag --registers"/>
      <property name="dut.object_messaging" value="false"/>
      <property name="dut.object_messaging.source" value="defaults"/>
      <property name="dut.pki" value="lab &amp; &lt;pki&gt;"/>
      <property name="dut.pki.source" value="dut.toml"/>
      <property name="device.identity" value="answered"/>
      <property name="device.vendor_name" value="mblab"/>
      <property name="device.product_code" value="MBLAB-REF"/>
      <property name="device.revision" value="0.1.0"/>
    </properties>
    <testcase classname="policy-2.1" name="7.3.1 Read coils" time="0.001500">
      <failure message="wrong transaction id" type="FAIL">CTP 7.3.1 (wrong transaction id)
cites Conformance Test Policy for the Modbus/TCP Conformance Test Laboratory, version 2.1 (University of Michigan), 7.3.1
sent      00 00 00 00 00 06 01 01 00 00 00 01
received  00 01 00 00 00 04 01 01 01 00
expected  00 00 00 00 00 04 01 01 01 XX
             ^^
</failure>
    </testcase>
    <testcase classname="policy-2.1" name="7.5.1 Read &lt;registers&gt; &amp; &quot;more&quot;" time="0.000500"/>
    <testcase classname="policy-2.1" name="7.13.1 Object messaging" time="0.000000">
      <skipped message="N/A: the DUT does not declare object_messaging"/>
    </testcase>
    <testcase classname="policy-2.1" name="7.2 Ping" time="0.000000">
      <skipped message="NOT RUN: no ICMP socket"/>
    </testcase>
  </testsuite>
</testsuites>
)");
}

TEST(JunitReport, SuiteTimesAddUpToTheTotal) {
    RunResult run = sample_run();
    SuiteResult second{"mbap", "MBAP", "mbap.toml", {}};
    second.cases.push_back({"mbap.1", "[TCPG]", "Header", Outcome{Verdict::Pass, "", {}},
                            std::chrono::microseconds(1234567), 1});
    run.suites.push_back(second);
    const std::string xml = junit_report(run, sample_provenance());
    EXPECT_NE(xml.find("tests=\"5\" failures=\"1\" errors=\"0\" time=\"1.236567\">"),
              std::string::npos)
        << xml;
    EXPECT_NE(xml.find("<testsuite name=\"policy-2.1\" tests=\"4\" failures=\"1\" errors=\"0\" "
                       "skipped=\"2\" time=\"0.002000\">"),
              std::string::npos);
    EXPECT_NE(xml.find("<testsuite name=\"mbap\" tests=\"1\" failures=\"0\" errors=\"0\" "
                       "skipped=\"0\" time=\"1.234567\">"),
              std::string::npos);
}

TEST(JunitReport, SaysWhyTheDeviceDidNotIdentifyItself) {
    Provenance provenance = sample_provenance();
    provenance.device = {false, "", "", "", "no answer within 1000 ms"};
    const std::string xml = junit_report(sample_run(), provenance);
    EXPECT_NE(xml.find("      <property name=\"device.identity\" value=\"not answered\"/>\n"
                       "      <property name=\"device.identity.reason\" "
                       "value=\"no answer within 1000 ms\"/>\n    </properties>\n"),
              std::string::npos)
        << xml;
}

struct Packet {
    std::vector<std::uint8_t> bytes;
    std::uint16_t source_port() const {
        return static_cast<std::uint16_t>(bytes[20] << 8 | bytes[21]);
    }
    std::uint16_t dest_port() const {
        return static_cast<std::uint16_t>(bytes[22] << 8 | bytes[23]);
    }
    std::uint32_t word(std::size_t at) const {
        return static_cast<std::uint32_t>(bytes[at] << 24 | bytes[at + 1] << 16 |
                                          bytes[at + 2] << 8 | bytes[at + 3]);
    }
    std::uint32_t seq() const { return word(24); }
    std::uint32_t ack() const { return word(28); }
    std::uint8_t flags() const { return bytes[33]; }
    std::vector<std::uint8_t> payload() const { return {bytes.begin() + 40, bytes.end()}; }
};

std::vector<Packet> read_pcap(const std::string& path, int& link_type) {
    char error[PCAP_ERRBUF_SIZE];
    std::unique_ptr<pcap_t, void (*)(pcap_t*)> handle(pcap_open_offline(path.c_str(), error),
                                                      &pcap_close);
    std::vector<Packet> packets;
    if (!handle) return packets;
    link_type = pcap_datalink(handle.get());
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(handle.get(), &header, &data) == 1) {
        packets.push_back({std::vector<std::uint8_t>(data, data + header->caplen)});
    }
    return packets;
}

std::vector<CaptureEvent> sample_capture() {
    Capture capture;
    capture.on_open({false, {127, 0, 0, 1}, 40001, {127, 0, 0, 1}, 1502});
    capture.on_sent(hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    capture.on_received(hex("00 00 00 00 00 05 01"));
    capture.on_received(hex("03 02 12 34"));
    capture.on_close(true);
    return capture.events();
}

TEST(PcapWriter, WritesRawIpv4WithConsistentSequenceNumbers) {
    const std::string path = test::temp_path("conform.pcap");
    std::string error;
    ASSERT_TRUE(write_pcap(path, sample_capture(), sample_provenance(), error)) << error;
    int link_type = 0;
    auto packets = read_pcap(path, link_type);
    EXPECT_EQ(link_type, DLT_RAW);
    // SYN, SYN-ACK, ACK, request, the answer (two reads, one frame), FIN, FIN, ACK.
    ASSERT_EQ(packets.size(), 8U);
    EXPECT_EQ(packets[0].flags(), 0x02);
    EXPECT_EQ(packets[1].flags(), 0x12);
    EXPECT_EQ(packets[1].ack(), packets[0].seq() + 1);
    const Packet& request = packets[3];
    EXPECT_EQ(request.source_port(), 40001);
    EXPECT_EQ(request.dest_port(), 502);  // the device's side is always 502
    EXPECT_EQ(request.payload(), hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    EXPECT_EQ(request.seq(), packets[0].seq() + 1);
    const Packet& answer = packets[4];
    EXPECT_EQ(answer.source_port(), 502);
    EXPECT_EQ(answer.seq(), packets[1].seq() + 1);
    EXPECT_EQ(answer.ack(), request.seq() + 12);
    EXPECT_EQ(answer.payload(), hex("00 00 00 00 00 05 01 03 02 12 34"));
    EXPECT_EQ(packets[5].source_port(), 502);  // the device closed first
    EXPECT_EQ(packets[5].flags(), 0x11);
    EXPECT_EQ(packets[5].seq(), answer.seq() + 11);
    EXPECT_EQ(packets[6].ack(), packets[5].seq() + 1);
    EXPECT_EQ(packets[7].flags(), 0x10);
}

// A connection over IPv6 is written as IPv6, with a TCP checksum over IPv6's pseudo-header.
TEST(PcapWriter, WritesAnIpv6ConnectionAsIpv6) {
    Capture capture;
    client::LinkAddresses addresses;
    addresses.ipv6 = true;
    addresses.local_ip[15] = 1;  // ::1
    addresses.local_port = 40002;
    addresses.peer_ip = {0xFD, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7};  // fd00::7
    addresses.peer_port = 1502;
    capture.on_open(addresses);
    capture.on_sent(hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    capture.on_close(false);
    const std::string path = test::temp_path("conform6.pcap");
    std::string error;
    ASSERT_TRUE(write_pcap(path, capture.events(), sample_provenance(), error)) << error;
    int link_type = 0;
    auto packets = read_pcap(path, link_type);
    ASSERT_EQ(packets.size(), 7U);
    const auto& request = packets[3].bytes;
    ASSERT_EQ(request.size(), 40U + 20U + 12U);
    EXPECT_EQ(request[0] >> 4, 6);
    EXPECT_EQ(request[4] << 8 | request[5], 32);  // payload length: TCP header and the request
    EXPECT_EQ(request[6], 6);                     // next header: TCP
    EXPECT_EQ(std::vector<std::uint8_t>(request.begin() + 8, request.begin() + 24),
              std::vector<std::uint8_t>(addresses.local_ip.begin(), addresses.local_ip.end()));
    EXPECT_EQ(std::vector<std::uint8_t>(request.begin() + 24, request.begin() + 40),
              std::vector<std::uint8_t>(addresses.peer_ip.begin(), addresses.peer_ip.end()));
    EXPECT_EQ(request[42] << 8 | request[43], 502);
    EXPECT_EQ(std::vector<std::uint8_t>(request.begin() + 60, request.end()),
              hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    // Summed with its pseudo-header (addresses, length, next header), a right segment gives FFFF.
    std::uint32_t sum = 32 + 6;
    for (std::size_t i = 8; i < request.size(); i += 2)
        sum += static_cast<std::uint32_t>(request[i] << 8 | request[i + 1]);
    while (sum >> 16)
        sum = (sum & 0xFFFF) + (sum >> 16);
    EXPECT_EQ(sum, 0xFFFFU);
}

TEST(PcapWriter, TsharkDissectsModbusWithoutMalformedPackets) {
    if (!std::filesystem::exists("/usr/bin/tshark")) GTEST_SKIP() << "tshark is not installed";
    const std::string path = test::temp_path("tshark.pcap");
    std::string error;
    ASSERT_TRUE(write_pcap(path, sample_capture(), sample_provenance(), error)) << error;
    const std::string command = "/usr/bin/tshark -r " + path +
                                " -Y mbtcp -T fields -e mbtcp.trans_id -e modbus.func_code "
                                "-e _ws.malformed 2>/dev/null";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(command.c_str(), "r"), &::pclose);
    ASSERT_TRUE(pipe);
    std::string output;
    char buffer[256];
    while (std::fgets(buffer, sizeof buffer, pipe.get()) != nullptr)
        output += buffer;
    EXPECT_EQ(output, "0\t3\t\n0\t3\t\n");
}

std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint32_t le32(const std::string& bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < 4; ++i)
        value |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    return value;
}

// The options of the section header block, by code, read as the pcapng draft lays them out.
std::vector<std::pair<std::uint16_t, std::string>> section_options(const std::string& bytes) {
    std::vector<std::pair<std::uint16_t, std::string>> options;
    const std::uint32_t length = le32(bytes, 4);
    std::size_t at = 24;  // type, length, byte-order magic, version, section length
    while (at + 4 <= length - 4) {
        const auto code = static_cast<std::uint16_t>(le32(bytes, at) & 0xFFFF);
        const std::uint32_t size = le32(bytes, at) >> 16;
        if (code == 0) break;
        options.emplace_back(code, bytes.substr(at + 4, size));
        at += 4 + (size + 3) / 4 * 4;
    }
    return options;
}

TEST(PcapWriter, IsPcapngWithTheProvenanceInTheSectionHeader) {
    const std::string path = test::temp_path("provenance.pcapng");
    std::string error;
    ASSERT_TRUE(write_pcap(path, sample_capture(), sample_provenance(), error)) << error;
    const std::string bytes = file_bytes(path);
    ASSERT_GT(bytes.size(), 28U);
    EXPECT_EQ(le32(bytes, 0), 0x0A0D0D0AU);  // section header block
    EXPECT_EQ(le32(bytes, 8), 0x1A2B3C4DU);  // byte-order magic
    EXPECT_EQ(le32(bytes, 4) % 4, 0U);
    EXPECT_EQ(le32(bytes, le32(bytes, 4) - 4), le32(bytes, 4));  // the length at both ends
    std::map<std::uint16_t, std::string> options;
    for (const auto& [code, value] : section_options(bytes))
        options[code] = value;
    EXPECT_EQ(options[4], "mblab 0.1.0 (commit abc1234)");  // shb_userappl
    EXPECT_FALSE(options[2].empty());                       // shb_hardware
    EXPECT_FALSE(options[3].empty());                       // shb_os
    EXPECT_EQ(options[1],                                   // opt_comment
              "mblab version: 0.1.0\n"
              "git commit: abc1234\n"
              "started: 2026-11-24T08:54:31Z\n"
              "finished: 2026-11-24T08:54:33Z\n"
              "command line: mblab conform tcp://127.0.0.1:1502 --registers 100 --case '7.5.*'\n"
              "declared by: flags\n"
              "dut unit: 1 (defaults)\n"
              "dut registers: 100 (flag --registers)\n"
              "dut object_messaging: false (defaults)\n"
              "dut pki: lab & <pki> (dut.toml)\n"
              "device identity: vendor name \"mblab\", product code \"MBLAB-REF\", revision "
              "\"0.1.0\"\n");
}

TEST(PcapWriter, ReportsAnUnwritablePath) {
    std::string error;
    EXPECT_FALSE(
        write_pcap("/nonexistent/dir/x.pcap", sample_capture(), sample_provenance(), error));
    EXPECT_EQ(error.rfind("cannot write /nonexistent/dir/x.pcap", 0), 0U) << error;
}

}  // namespace
}  // namespace mblab::conformance
