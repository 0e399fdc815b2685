#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "conform_client_support.hpp"
#include "support/temp_dir.hpp"
#include "support/temp_path.hpp"

// `mblab conform-client` on a serial line: the examiner makes a pty pair (rtu:///dev/ptmx) and
// gives the client its end in {url}. `mblab read` and a well-behaved RTU master pass every
// scenario that applies to them; an RTU master built with one defect fails that scenario only.
// Declarations come from a TOML file too, flags put over them.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using Verdicts = ClientVerdicts;

Verdicts examine(const std::string& listen, std::vector<std::string> flags,
                 const std::vector<std::string>& client) {
    std::vector<std::string> argv = {MBLAB_BINARY, "conform-client", "--listen",
                                     listen,       "--json",         "-"};
    argv.insert(argv.end(), flags.begin(), flags.end());
    argv.push_back("--");
    argv.insert(argv.end(), client.begin(), client.end());
    return client_verdicts(argv);
}

const std::vector<std::string> kDeclared = {"--client-timeout", "300", "--client-retries", "1"};

std::vector<std::string> rtu_master(const std::string& defect) {
    std::vector<std::string> argv = {"python3", kModbusClient, "{url}",   "-",
                                     "{unit}",  "{address}",   "{count}", "--timeout",
                                     "0.3",     "--retries",   "1"};
    if (!defect.empty()) argv.insert(argv.end(), {"--defect", defect});
    return argv;
}

std::vector<std::string> mblab_read() {
    return {MBLAB_BINARY, "read",      "{url}", "holding",   "{address}", "{count}",   "--unit",
            "{unit}",     "--timeout", "300",   "--retries", "1",         "--no-probe"};
}

// Every case is PASS but those in `failing` (FAIL) and `na` (N/A).
void expect_only(const Verdicts& verdicts, const std::vector<std::string>& failing,
                 const std::vector<std::string>& na = {}) {
    expect_verdicts(verdicts, 12U, failing, na);
}

TEST(ConformClientLine, MblabReadPassesEveryScenarioThatAppliesOverRtuAndAscii) {
    // mblab sends no broadcasts, and says so: scenario 9 is N/A for it.
    expect_only(examine("rtu:///dev/ptmx?baud=19200", kDeclared, mblab_read()), {}, {"ser.9"});
    // A pty refuses 7 data bits: ASCII is examined with 8.
    expect_only(examine("ascii:///dev/ptmx?data=8", kDeclared, mblab_read()), {}, {"ser.9"});
}

TEST(ConformClientLine, AWellBehavedRtuMasterPassesEveryScenarioBroadcastIncluded) {
    auto flags = kDeclared;
    flags.push_back("--client-broadcast");
    expect_only(examine("rtu:///dev/ptmx", flags, rtu_master("")), {});
}

TEST(ConformClientLine, TakingAnotherSlavesReplyFailsThatScenarioOnly) {
    expect_only(examine("rtu:///dev/ptmx", kDeclared, rtu_master("wrong-slave")), {"ser.4"},
                {"ser.9"});
}

TEST(ConformClientLine, WaitingForAnAnswerToABroadcastFailsTheBroadcastOnly) {
    auto flags = kDeclared;
    flags.push_back("--client-broadcast");
    expect_only(examine("rtu:///dev/ptmx", flags, rtu_master("broadcast-wait")), {"ser.9"});
}

TEST(ConformClientLine, DeclarationsFromAFileWithFlagsOverThem) {
    const auto file = temp_path("client-declarations.toml");
    std::ofstream(file) << "client-timeout = 300\nclient-retries = 1\n"
                           "client-broadcast = true\nclient-unit = 7\n";
    // The file declares broadcasts; unit 7 from the file is replaced by the flag's 1.
    const auto verdicts =
        examine("rtu:///dev/ptmx",
                {"--declare", file, "--client-unit", "1", "--case", "ser.9", "--case", "ser.4"},
                rtu_master(""));
    EXPECT_EQ(verdicts.status, 0) << verdicts.console;
    EXPECT_EQ(verdicts.by_case.at("ser.9"), "PASS") << verdicts.console;
    EXPECT_EQ(verdicts.by_case.at("ser.4"), "PASS") << verdicts.console;
    const auto shown = run_program({MBLAB_BINARY, "conform-client", "--listen", "rtu:///dev/ptmx",
                                    "--declare", file, "--case", "ser.9", "--", "true"});
    EXPECT_THAT(shown.out, HasSubstr("Client: unit 7, registers 100..101, timeout 300 ms, "
                                     "retries 1, broadcasts"));
}

TEST(ConformClientLine, BadDeclarationFilesAreOneLineErrors) {
    const auto file = temp_path("bad-declarations.toml");
    const std::pair<std::string, std::string> cases[] = {
        {"client-timout = 300\n", ":1: unknown key 'client-timout' (known keys: client-unit"},
        {"client-unit = 300\n", ":1: 'client-unit' must be an integer from 0 to 255"},
        {"client-broadcast = 1\n", "'client-broadcast' must be true or false"},
        {"error-pattern = \"(\"\n", "error-pattern: not a regular expression"},
    };
    for (const auto& [text, expected] : cases) {
        std::ofstream(file) << text;
        const auto ran =
            run_program({MBLAB_BINARY, "conform-client", "--declare", file, "--", "true"});
        EXPECT_EQ(ran.status, 2) << text;
        EXPECT_THAT(ran.err, HasSubstr(expected)) << text;
        EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;
    }
}

// RTU frames over TCP (a client of a serial gateway): the line's scenarios on TCP connections,
// the capture's frames RTU on USER0.
TEST(ConformClientLine, OverRtuTcpMblabReadPassesTheLineScenarios) {
    const auto pcap = temp_path("rtu-tcp.pcapng");
    const auto verdicts =
        examine("rtu+tcp://127.0.0.1:0",
                {"--client-timeout", "300", "--client-retries", "1", "--pcap", pcap}, mblab_read());
    expect_only(verdicts, {}, {"ser.9"});
    EXPECT_THAT(verdicts.console, HasSubstr("client-rtu-tcp: a Modbus RTU client (master) over "
                                            "TCP, as through a serial gateway"));
    const auto frames = file_text(pcap);
    EXPECT_THAT(frames, HasSubstr(std::string("\x93\x00\x00\x00", 4)));  // USER0
    EXPECT_THAT(frames, HasSubstr(std::string("\x01\x03\x00\x64\x00\x02\x85\xD4", 8)));
    EXPECT_THAT(frames, HasSubstr("ser.6.0B"));
}

// The line's frames in pcapng: RTU on link type USER0 (147), ASCII as its text on USER1 (148),
// each labelled with its scenario.
TEST(ConformClientLine, TheCaptureHoldsTheLinesFramesUnderTheScenariosId) {
    const auto rtu = temp_path("line.pcapng");
    auto argv = rtu_master("wrong-slave");
    argv.insert(argv.begin(), {MBLAB_BINARY, "conform-client", "--listen",
                               "rtu:///dev/ptmx?baud=19200", "--client-timeout", "300",
                               "--client-retries", "1", "--case", "ser.4", "--pcap", rtu, "--"});
    EXPECT_EQ(run_program(argv, std::chrono::seconds(60)).status, 1);
    const auto frames = file_text(rtu);
    EXPECT_EQ(frames.substr(0, 4), std::string("\x0A\x0D\x0D\x0A", 4));
    EXPECT_THAT(frames, HasSubstr(std::string("\x93\x00\x00\x00", 4)));  // USER0
    EXPECT_THAT(frames, HasSubstr("ser.4"));
    EXPECT_THAT(frames, HasSubstr(std::string("\x01\x03\x00\x64\x00\x02\x85\xD4", 8)));
    EXPECT_THAT(frames, HasSubstr(std::string("\x02\x03\x04\x9C\xA4\x9C\xA5\x0F\xFB", 9)));

    const auto ascii = temp_path("line-ascii.pcapng");
    auto read = mblab_read();
    read.insert(read.begin(),
                {MBLAB_BINARY, "conform-client", "--listen", "ascii:///dev/ptmx?data=8", "--case",
                 "ser.6.02", "--pcap", ascii, "--"});
    EXPECT_EQ(run_program(read, std::chrono::seconds(60)).status, 0);
    const auto text = file_text(ascii);
    EXPECT_THAT(text, HasSubstr(std::string("\x94\x00\x00\x00", 4)));  // USER1
    EXPECT_THAT(text, HasSubstr(":010300640002"));
    EXPECT_THAT(text, HasSubstr(":018302"));
}

}  // namespace
}  // namespace mblab::test
