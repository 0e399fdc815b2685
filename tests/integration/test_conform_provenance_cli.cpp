#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <toml++/toml.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

// Where a report of `mblab conform` came from, as the report files of a real run say it: the
// build, the time, the command line, the declarations with their sources and the device's own
// identification; and the JUnit file valid against Jenkins' junit-10 schema.
namespace mblab::conformance {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

using test::Ran;

// Runs any program to its end and collects its output.
Ran run(const std::vector<std::string>& argv) {
    return test::run_program(argv, std::chrono::seconds(60));
}

// "mblab 0.1.0 (commit abc1234)" as `mblab --version` prints it: {version, commit}.
std::pair<std::string, std::string> printed_version() {
    const Ran ran = test::run_mblab({"--version"});
    std::smatch parts;
    const std::regex pattern("mblab (\\S+) \\(commit (\\S+)\\)\n");
    if (!std::regex_match(ran.out, parts, pattern)) {
        ADD_FAILURE() << "mblab --version printed " << ran.out;
        return {};
    }
    return {parts[1], parts[2]};
}

bool is_recent_utc_time(const std::string& text) {
    std::tm parsed{};
    if (!std::regex_match(text, std::regex("\\d{4}-\\d\\d-\\d\\dT\\d\\d:\\d\\d:\\d\\dZ")) ||
        ::strptime(text.c_str(), "%Y-%m-%dT%H:%M:%SZ", &parsed) == nullptr) {
        return false;
    }
    const std::time_t then = ::timegm(&parsed);
    const std::time_t now = std::time(nullptr);
    return then <= now && now - then < 600;
}

// The built-in device's identification objects, from the shipped profile itself.
struct Identity {
    std::string vendor;
    std::string product_code;
    std::string revision;
};

Identity reference_identity() {
    const auto profile =
        toml::parse_file(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
    const auto* identification = profile["unit"][0]["identification"].as_table();
    if (identification == nullptr) {
        ADD_FAILURE() << "profiles/reference.toml has no [unit.identification]";
        return {};
    }
    return {identification->get("vendor")->value_or(std::string()),
            identification->get("product_code")->value_or(std::string()),
            identification->get("revision")->value_or(std::string())};
}

const nlohmann::json* declaration(const nlohmann::json& provenance, const std::string& key) {
    for (const auto& entry : provenance["declarations"]) {
        if (entry["key"] == key) return &entry;
    }
    return nullptr;
}

TEST(ConformProvenanceCli, TheJsonReportSaysWhereItCameFrom) {
    test::TempDir dir;
    const std::string json = (dir / "report.json").string();
    const std::vector<std::string> args = {"conform", "--suite", "mbap", "--case",
                                           "mbap.1",  "--json",  json};
    auto ran = test::run_mblab(args);
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto report = nlohmann::json::parse(test::file_text(json));
    const auto& provenance = report["provenance"];

    const auto [version, commit] = printed_version();
    EXPECT_EQ(provenance["mblab_version"], version);
    EXPECT_EQ(provenance["mblab_version"], MBLAB_VERSION);
    EXPECT_EQ(provenance["git_commit"], commit);

    std::vector<std::string> argv = {MBLAB_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    EXPECT_EQ(provenance["command_line"], argv);

    EXPECT_TRUE(is_recent_utc_time(provenance["started"])) << provenance["started"];
    EXPECT_TRUE(is_recent_utc_time(provenance["finished"])) << provenance["finished"];
    EXPECT_LE(provenance["started"].get<std::string>(), provenance["finished"].get<std::string>());

    EXPECT_EQ(provenance["declared_by"], "profile reference.toml");
    const auto* unit = declaration(provenance, "unit");
    ASSERT_NE(unit, nullptr) << provenance;
    EXPECT_EQ((*unit)["value"], 1);
    EXPECT_EQ((*unit)["source"], "profile reference.toml");
    ASSERT_NE(declaration(provenance, "registers"), nullptr);
    EXPECT_EQ(report["dut"]["registers"], (*declaration(provenance, "registers"))["value"]);

    const Identity expected = reference_identity();
    EXPECT_EQ(provenance["device_identity"]["status"], "answered") << provenance;
    EXPECT_EQ(provenance["device_identity"]["vendor_name"], expected.vendor);
    EXPECT_EQ(provenance["device_identity"]["product_code"], expected.product_code);
    EXPECT_EQ(provenance["device_identity"]["revision"], expected.revision);
    EXPECT_EQ(expected.vendor, "mblab");  // the profile was read
}

TEST(ConformProvenanceCli, EachDeclarationNamesItsSource) {
    test::TempDir dir;
    const std::string json = (dir / "report.json").string();
    const std::string dut = (dir / "dut.toml").string();
    std::ofstream(dut) << "registers = 200\ncoils = 16\n";
    auto ran = test::run_mblab({"conform", "--suite", "mbap", "--case", "mbap.1", "--dut", dut,
                                "--registers", "100", "--json", json});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto provenance = nlohmann::json::parse(test::file_text(json))["provenance"];
    EXPECT_EQ(provenance["declared_by"], dut + " and flags");
    ASSERT_NE(declaration(provenance, "registers"), nullptr);
    EXPECT_EQ((*declaration(provenance, "registers"))["value"], 100);
    EXPECT_EQ((*declaration(provenance, "registers"))["source"], "flag --registers");
    ASSERT_NE(declaration(provenance, "coils"), nullptr);
    EXPECT_EQ((*declaration(provenance, "coils"))["value"], 16);
    EXPECT_EQ((*declaration(provenance, "coils"))["source"], dut);
    // The file replaces the profile's declaration: what it leaves out is a default.
    ASSERT_NE(declaration(provenance, "max_read"), nullptr);
    EXPECT_EQ((*declaration(provenance, "max_read"))["source"], "defaults");
    EXPECT_EQ(declaration(provenance, "input_registers"), nullptr);
}

TEST(ConformProvenanceCli, ADeviceWithoutIdentificationIsNotAnsweredAndTheRunGoesOn) {
    test::TempDir dir;
    const std::string json = (dir / "report.json").string();
    const std::string profile = (dir / "plain.toml").string();
    std::ofstream(profile) << "name = \"plain\"\n\n[[unit]]\nid = 1\nname = \"plain\"\n"
                              "functions = [3]\n\n[[unit.holding_registers]]\nstart = 0\n"
                              "count = 10\n";
    auto ran = test::run_mblab(
        {"conform", "--profile", profile, "--suite", "mbap", "--case", "mbap.1", "--json", json});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto identity =
        nlohmann::json::parse(test::file_text(json))["provenance"]["device_identity"];
    EXPECT_EQ(identity, (nlohmann::json{{"status", "not answered"},
                                        {"reason", "exception 01 (illegal function)"}}));
}

TEST(ConformProvenanceCli, TheJunitReportValidatesAgainstJunit10AndCarriesTheProvenance) {
    if (!fs::exists("/usr/bin/xmllint")) GTEST_SKIP() << "xmllint (libxml2-utils) is not installed";
    test::TempDir dir;
    const std::string junit = (dir / "report.xml").string();
    // Suites of every verdict: N/A and NOT RUN cases give <skipped>.
    auto ran =
        test::run_mblab({"conform", "--suite", "policy-2.1", "--suite", "mbap", "--junit", junit});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    const Ran lint = run({"/usr/bin/xmllint", "--noout", "--schema",
                          std::string(MBLAB_SOURCE_DIR) + "/tests/junit-10.xsd", junit});
    EXPECT_EQ(lint.status, 0) << lint.out << lint.err;
    EXPECT_EQ(lint.err, junit + " validates\n");

    const std::string xml = test::file_text(junit);
    const auto [version, commit] = printed_version();
    EXPECT_NE(xml.find("<property name=\"mblab.version\" value=\"" + version + "\"/>"),
              std::string::npos)
        << xml;
    EXPECT_NE(xml.find("<property name=\"mblab.commit\" value=\"" + commit + "\"/>"),
              std::string::npos);
    EXPECT_NE(xml.find("<property name=\"run.command_line\" value=\"" + std::string(MBLAB_BINARY) +
                       " conform --suite policy-2.1 --suite mbap --junit " + junit + "\"/>"),
              std::string::npos);
    EXPECT_THAT(xml,
                HasSubstr("<property name=\"dut.unit.source\" value=\"profile reference.toml\"/>"));
    EXPECT_NE(xml.find("<property name=\"device.vendor_name\" value=\"" +
                       reference_identity().vendor + "\"/>"),
              std::string::npos);
    // One <properties> per suite: junit-10 has none on <testsuites>.
    std::size_t suites = 0;
    for (auto at = xml.find("<properties>"); at != std::string::npos;
         at = xml.find("<properties>", at + 1))
        ++suites;
    EXPECT_EQ(suites, 2U);
}

TEST(ConformProvenanceCli, ThePcapngCarriesTheProvenanceAndTsharkReadsIt) {
    if (!fs::exists("/usr/bin/tshark") || !fs::exists("/usr/bin/capinfos"))
        GTEST_SKIP() << "tshark is not installed";
    test::TempDir dir;
    const std::string pcap = (dir / "run.pcapng").string();
    auto ran = test::run_mblab({"conform", "--suite", "mbap", "--case", "mbap.1", "--pcap", pcap});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;

    const Ran read = run({"/usr/bin/tshark", "-r", pcap, "-Y", "mbtcp"});
    EXPECT_EQ(read.status, 0) << read.err;
    // The identification request is in the capture too, after the case's exchanges.
    EXPECT_THAT(read.out, HasSubstr("Read Device Identification"));

    const Ran info = run({"/usr/bin/capinfos", "-k", "-t", pcap});
    EXPECT_EQ(info.status, 0) << info.err;
    EXPECT_THAT(info.out, HasSubstr("pcapng"));
    const auto [version, commit] = printed_version();
    EXPECT_NE(info.out.find("mblab version: " + version), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("git commit: " + commit), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("command line: " + std::string(MBLAB_BINARY) +
                            " conform --suite mbap --case mbap.1 --pcap " + pcap),
              std::string::npos)
        << info.out;
    EXPECT_THAT(info.out, HasSubstr("declared by: profile reference.toml"));
    EXPECT_NE(info.out.find("device identity: vendor name \"" + reference_identity().vendor),
              std::string::npos)
        << info.out;
}

// A device reached over IPv6 is captured as IPv6 and pinged over ICMPv6.
TEST(ConformProvenanceCli, AnIpv6RunIsCapturedAsIpv6AndPingedOverIcmpv6) {
    if (!fs::exists("/usr/bin/tshark")) GTEST_SKIP() << "tshark is not installed";
    test::ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://[::1]:0"});
    const auto line = serve.read_stdout_line(std::chrono::seconds(10)).value_or("");
    std::smatch port;
    ASSERT_TRUE(std::regex_search(line, port, std::regex(R"(tcp://\[::1\]:([0-9]+))"))) << line;
    test::TempDir dir;
    const std::string pcap = (dir / "run6.pcapng").string();
    const std::string json = (dir / "run6.json").string();
    auto ran =
        test::run_mblab({"conform", "tcp://[::1]:" + port[1].str(), "--suite", "policy-2.1",
                         "--case", "7.2", "--case", "7.3.1", "--pcap", pcap, "--json", json});
    EXPECT_NE(ran.status, 2) << ran.out << ran.err;

    const Ran read = run({"/usr/bin/tshark", "-r", pcap, "-Y", "mbtcp", "-T", "fields", "-e",
                          "ipv6.src", "-e", "ipv6.dst", "-e", "ip.src"});
    EXPECT_EQ(read.status, 0) << read.err;
    ASSERT_FALSE(read.out.empty());
    EXPECT_EQ(read.out.find("127.0.0.1"), std::string::npos) << read.out;
    std::istringstream rows(read.out);
    for (std::string row; std::getline(rows, row);)
        EXPECT_EQ(row, "::1\t::1\t") << read.out;

    // Ping's verdict depends on the machine's ICMP permissions, so only its method is checked.
    const auto report = nlohmann::json::parse(test::file_text(json));
    bool ping = false;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"]) {
            if (c["id"] != "7.2") continue;
            ping = true;
            EXPECT_NE(c["reason"].get<std::string>().find("ICMPv6"), std::string::npos) << c;
        }
    }
    EXPECT_TRUE(ping) << report.dump();
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(std::chrono::seconds(10)), 0);
}

}  // namespace
}  // namespace mblab::conformance
