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

TEST(ConformClientLine, UsageErrors) {
    const auto gateway = run_program(
        {MBLAB_BINARY, "conform-client", "--listen", "rtu+tcp://127.0.0.1:5020", "--", "true"});
    EXPECT_EQ(gateway.status, 2);
    EXPECT_THAT(gateway.err, HasSubstr("rtu+tcp:// is not examined yet"));
    const auto pcap = run_program({MBLAB_BINARY, "conform-client", "--listen", "rtu:///dev/ptmx",
                                   "--pcap", temp_path("line.pcapng"), "--", "true"});
    EXPECT_EQ(pcap.status, 2);
    EXPECT_THAT(pcap.err, HasSubstr("a serial line is not captured yet"));
}

}  // namespace
}  // namespace mblab::test
