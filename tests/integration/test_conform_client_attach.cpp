#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "conform_client_support.hpp"
#include "support/temp_path.hpp"

// `mblab conform-client --attach`: no command is run; tests/clients/modbus_client.py --poll
// polls the examiner by itself as a PLC does, and each scenario judges its requests alone.
namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

struct Attached {
    ClientVerdicts verdicts;
    std::string console;
};

// Starts the examiner with --attach on a free port, then the polling client at the port the
// examiner's first line names; the verdicts come from the JSON report.
Attached attach(const std::vector<std::string>& more, const std::string& defect) {
    const auto json = temp_path("conform-client-attach.json");
    std::vector<std::string> argv = {
        MBLAB_BINARY, "conform-client", "--attach", "--client-timeout", "300ms", "--client-retries",
        "1",          "--json",         json};
    argv.insert(argv.end(), more.begin(), more.end());
    ChildProcess examiner(argv);
    Attached attached;
    const auto first = examiner.read_stdout_line(10s);
    if (!first) {
        ADD_FAILURE() << "the examiner printed nothing";
        return attached;
    }
    attached.console = *first + "\n";
    const auto colon = first->rfind(':');
    const auto port = first->substr(colon + 1, first->find(' ', colon) - colon - 1);
    std::vector<std::string> client = {
        "/usr/bin/env", "python3", kModbusClient, "127.0.0.1", port,     "1",  "100", "2",
        "--timeout",    "0.3",     "--retries",   "1",         "--poll", "1.0"};
    if (!defect.empty()) client.insert(client.end(), {"--defect", defect});
    std::unique_ptr<ChildProcess> polling = std::make_unique<ChildProcess>(client);
    while (auto line = examiner.read_stdout_line(120s))
        attached.console += *line + "\n";
    attached.verdicts.status = examiner.wait_exit(10s).value_or(-1);
    polling.reset();  // stops the client, by its own pid
    std::ifstream file(json);
    std::stringstream text;
    text << file.rdbuf();
    const auto report = nlohmann::json::parse(text.str(), nullptr, false);
    if (report.is_discarded()) {
        ADD_FAILURE() << "no JSON report: " << attached.console;
        return attached;
    }
    for (const auto& c : report["suites"][0]["cases"])
        attached.verdicts.by_case[c["id"].get<std::string>()] = c["verdict"].get<std::string>();
    attached.verdicts.console = attached.console;
    return attached;
}

// The scenarios an attached client cannot be judged on: whether it took a decoy shows only in
// its output.
const std::vector<std::string> kNeedOutput = {"tcp.2",   "tcp.3",   "tcp.4",   "tcp.5.1", "tcp.5.2",
                                              "tcp.5.3", "tcp.7.1", "tcp.7.2", "tcp.10",  "tcp.11"};

TEST(ConformClientAttach, APollingClientIsJudgedByItsRequestsAlone) {
    const auto attached = attach({}, "");
    expect_verdicts(attached.verdicts, 21U, {}, kNeedOutput);
    EXPECT_THAT(attached.console, HasSubstr(" --attach\nAttached: each scenario waits up to 60 s "
                                            "for the client to poll, then watches it until it "
                                            "is quiet for 550 ms"));
    EXPECT_THAT(attached.console, HasSubstr("tcp.1     no reply: times out, retries as declared, "
                                            "then an error  (2 requests, each after its timeout)"));
    EXPECT_THAT(attached.console, HasSubstr("(--attach: whether the client took the decoys shows "
                                            "only in its output"));
    EXPECT_THAT(attached.console, HasSubstr("tcp.6.05  exception 05 is an error, never a value  "
                                            "(asked 1 time)"));
}

TEST(ConformClientAttach, AClientThatRetriesForeverFailsTheNoReplyOnly) {
    const auto attached = attach({}, "retry-forever");
    expect_verdicts(attached.verdicts, 21U, {"tcp.1"}, kNeedOutput);
    EXPECT_THAT(attached.console, HasSubstr("a resend storm"));
}

TEST(ConformClientAttach, NoClientWithinTheWaitIsNotRun) {
    const auto ran =
        run_program({MBLAB_BINARY, "conform-client", "--attach", "--client-timeout", "300ms",
                     "--client-retries", "1", "--attach-wait", "300ms", "--case", "tcp.1"});
    EXPECT_EQ(ran.status, 0) << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("NOT RUN  tcp.1"));
    EXPECT_THAT(ran.out, HasSubstr("(the client sent nothing within 300 ms of waiting"));
}

TEST(ConformClientAttach, UsageErrors) {
    const auto command = run_program(
        {MBLAB_BINARY, "conform-client", "--attach", "--client-timeout", "1s", "--", "true"});
    EXPECT_EQ(command.status, 2);
    EXPECT_THAT(command.err, HasSubstr("--attach watches a client that runs by itself: give no "
                                       "command"));
    const auto timeout = run_program({MBLAB_BINARY, "conform-client", "--attach"});
    EXPECT_EQ(timeout.status, 2);
    EXPECT_THAT(timeout.err, HasSubstr("--attach needs --client-timeout"));
}

}  // namespace
}  // namespace mblab::test
