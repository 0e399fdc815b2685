#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "conform_client_support.hpp"
#include "support/temp_path.hpp"

// `mblab conform-client` against clients built wrong on purpose (tests/clients/modbus_client.py,
// one defect each) and against `mblab read`: each defect FAILs the scenario it is about and no
// other; the well-behaved clients pass every scenario that applies.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

const std::string& kClient = kModbusClient;
using Verdicts = ClientVerdicts;

// Runs conform-client with the declarations (timeout 300 ms, `retries`) and `client`, its
// JSON report on standard output.
Verdicts examine(unsigned retries, std::vector<std::string> client) {
    std::vector<std::string> argv = {MBLAB_BINARY,
                                     "conform-client",
                                     "--client-timeout",
                                     "300ms",
                                     "--client-retries",
                                     std::to_string(retries),
                                     "--json",
                                     "-",
                                     "--"};
    argv.insert(argv.end(), client.begin(), client.end());
    return client_verdicts(argv);
}

// Every case is PASS but those in `failing` (FAIL) and `na` (N/A).
void expect_only(const Verdicts& verdicts, const std::vector<std::string>& failing,
                 const std::vector<std::string>& na = {"tcp.11"}) {
    expect_verdicts(verdicts, 21U, failing, na);
}

TEST(ConformClientCli, MblabReadPassesEveryScenarioThatApplies) {
    const auto verdicts =
        examine(1, {MBLAB_BINARY, "read", "{url}", "holding", "{address}", "{count}", "--unit",
                    "{unit}", "--timeout", "300", "--retries", "1", "--no-probe"});
    expect_only(verdicts, {});
}

TEST(ConformClientCli, AWellBehavedClientPassesEveryScenario) {
    expect_only(examine(1, python_client(1, "")), {});
}

TEST(ConformClientCli, TakingAStaleAnswerFailsTheLateReplyOnly) {
    const auto verdicts = examine(1, python_client(1, "stale"));
    expect_only(verdicts, {"tcp.2"});
    EXPECT_THAT(verdicts.console,
                HasSubstr("took the decoy 40100 from 00 01 00 00 00 07 01 03 04 9C A4 9C A5"));
}

TEST(ConformClientCli, IgnoringTransactionIdsFailsTheWrongTransactionOnly) {
    // Without retries the stale answer meets no later request: that scenario is N/A.
    expect_only(examine(0, python_client(0, "ignore-tid")), {"tcp.3"}, {"tcp.2", "tcp.11"});
}

TEST(ConformClientCli, AnExceptionReportedAsZeroFailsTheExceptionsOnly) {
    expect_only(examine(1, python_client(1, "exception-zero")),
                {"tcp.6.01", "tcp.6.02", "tcp.6.03", "tcp.6.04", "tcp.6.05", "tcp.6.06", "tcp.6.0A",
                 "tcp.6.0B"});
}

TEST(ConformClientCli, NeverTimingOutFailsTheNoReplyOnly) {
    const auto verdicts = examine(0, python_client(0, "no-timeout"));
    expect_only(verdicts, {"tcp.1"}, {"tcp.2", "tcp.11"});
    EXPECT_THAT(verdicts.console, HasSubstr("it never timed out"));
}

TEST(ConformClientCli, RetryingForeverFailsTheNoReplyOnly) {
    const auto verdicts = examine(1, python_client(1, "retry-forever"));
    expect_only(verdicts, {"tcp.1"});
    EXPECT_THAT(verdicts.console, HasSubstr("a resend storm"));
}

TEST(ConformClientCli, TakingAnotherUnitsReplyFailsTheWrongUnitOnly) {
    expect_only(examine(1, python_client(1, "wrong-unit")), {"tcp.4"});
}

// tcp.11 alone: a pipelining client sends two requests at once in every scenario.
TEST(ConformClientCli, PipelinedAnswersPairedByArrivalFail) {
    for (const std::string defect : {"", "fifo"}) {
        std::vector<std::string> argv = {
            MBLAB_BINARY, "conform-client", "--case",  "tcp.11",    "--client-pipelining",
            "--",         "python3",        kClient,   "{host}",    "{port}",
            "{unit}",     "{address}",      "{count}", "--pipeline"};
        if (!defect.empty()) argv.insert(argv.end(), {"--defect", defect});
        const auto ran = run_program(argv, std::chrono::seconds(60));
        EXPECT_EQ(ran.status, defect.empty() ? 0 : 1) << ran.out << ran.err;
        EXPECT_THAT(ran.out,
                    HasSubstr(defect.empty() ? "  PASS     tcp.11 " : "  FAIL     tcp.11 "));
    }
    const auto ran =
        run_program({MBLAB_BINARY, "conform-client", "--case", "tcp.11", "--", "true"});
    EXPECT_THAT(ran.out, HasSubstr("N/A      tcp.11"));
}

TEST(ConformClientCli, UndeclaredTimeoutAndRetriesAreNotApplicable) {
    const auto ran = run_program(
        {MBLAB_BINARY, "conform-client", "--case", "tcp.1", "--case", "tcp.2", "--", "true"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("N/A      tcp.1     no reply: times out, retries as declared, "
                                   "then an error  (the client's timeout is not declared "
                                   "(--client-timeout))"));
}

TEST(ConformClientCli, UsageErrors) {
    const auto no_command = run_program({MBLAB_BINARY, "conform-client"});
    EXPECT_EQ(no_command.status, 2);
    EXPECT_THAT(no_command.err, HasSubstr("give the client's command after --"));
    const auto regex =
        run_program({MBLAB_BINARY, "conform-client", "--error-pattern", "(", "--", "true"});
    EXPECT_EQ(regex.status, 2);
    EXPECT_THAT(regex.err, HasSubstr("--error-pattern: not a regular expression"));
}

std::string slurp(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

TEST(ConformClientCli, TheJUnitReportAndTheCaptureNameTheCommandAndTheScenario) {
    const auto junit = temp_path("conform-client.xml");
    const auto pcap = temp_path("conform-client.pcapng");
    auto argv = python_client(0, "exception-zero");
    argv.insert(argv.begin(), {MBLAB_BINARY, "conform-client", "--case", "tcp.6.02", "--junit",
                               junit, "--pcap", pcap, "--"});
    const auto ran = run_program(argv, std::chrono::seconds(60));
    EXPECT_EQ(ran.status, 1) << ran.err;
    const auto xml = slurp(junit);
    EXPECT_THAT(xml, HasSubstr("<testsuites name=\"mblab conform-client tcp://127.0.0.1:"));
    EXPECT_THAT(xml, HasSubstr("<failure message=\"exception 02 reported as success, not as "
                               "an error; output: &quot;0 0&quot;\""));
    // pcapng (its section header block first), the scenario's id as the packets' comment and the
    // exception answer among the packets.
    const auto capture = slurp(pcap);
    EXPECT_EQ(capture.substr(0, 4), std::string("\x0A\x0D\x0D\x0A", 4));
    EXPECT_THAT(capture, HasSubstr("tcp.6.02"));
    EXPECT_THAT(capture, HasSubstr(std::string("\x00\x03\x01\x83\x02", 5)));
}

TEST(ConformClientCli, AClientThatSendsNothingFails) {
    const auto ran = run_program({MBLAB_BINARY, "conform-client", "--case", "tcp.3", "--", "true"});
    EXPECT_EQ(ran.status, 1);
    EXPECT_THAT(ran.out, HasSubstr("sent no request to unit 1 (exit status 0)"));
}

}  // namespace
}  // namespace mblab::test
