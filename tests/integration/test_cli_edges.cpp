// Small edges of the command line, with the real binary: durations as plain numbers and as
// load's run length, --help in mblab's words, reports on standard output, reports never left
// empty. (A restart that a device in listen only mode rightly leaves unanswered:
// test_client_commands.cpp.)
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "http_serve.hpp"
#include "support/temp_dir.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(CliEdges, APlainFractionalDurationIsInTheOptionsUnit) {
    // Milliseconds held whole: half of one is refused as 500us is, and says what 0.5s would be.
    auto ran = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--timeout", "0.5"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_THAT(ran.err, HasSubstr("--timeout: '0.5' is not a whole number of milliseconds (a "
                                   "number alone is milliseconds: 0.5s is 500)"));
    ran = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--timeout", "100us"});
    EXPECT_THAT(ran.err, HasSubstr("--timeout: '100us' is not a whole number of milliseconds"));
    // Taken: the run gets as far as the connection.
    ran =
        run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--timeout", "1.5s", "--no-probe"});
    EXPECT_THAT(ran.err, HasSubstr("cannot connect"));
    // Seconds: a fraction is a duration like any other.
    ChildProcess serve(serve_argv({"--idle-timeout", "0.5", "--save-interval", "0.25"}));
    EXPECT_FALSE(modbus_target(serve).empty());
}

TEST(CliEdges, LoadTakesDurationsAsEveryOtherOptionDoes) {
    ChildProcess serve(serve_argv({}));
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    // With a unit, bare (seconds, as ever), in milliseconds, and as a sum of parts.
    for (const char* given : {"0.5s", "0.5", "500ms", "0m0.5s"}) {
        auto load =
            run_mblab({"load", target, "--duration", given, "--connections", "1", "--json", "-"});
        EXPECT_EQ(load.status, 0) << given << ": " << load.err;
        const auto report = nlohmann::json::parse(load.out, nullptr, false);
        EXPECT_EQ(report.value("duration_s", 0.0), 0.5) << given;
    }
    auto refused = run_mblab({"load", target, "--duration", "1m30"});
    EXPECT_EQ(refused.status, 2);
    EXPECT_THAT(refused.err, HasSubstr("--duration: '1m30' is not a duration: give e.g. 250ms"));
    refused = run_mblab({"load", target, "--duration", "0"});
    EXPECT_EQ(refused.status, 2);
    EXPECT_THAT(refused.err, HasSubstr("--duration: a run lasts from 1ms to a year"));
    EXPECT_THAT(run_mblab({"load", "--help"}).out, HasSubstr("--duration DURATION=1h "));
}

TEST(CliEdges, HelpNamesValuesInMblabsWords) {
    for (const char* command : {"conform", "read", "serve", "load", "fuzz", "watch"}) {
        const auto help = run_mblab({command, "--help"}).out;
        for (const char* artefact : {"UINT", "INT in [", "TEXT:FILE", "TEXT:{", ":INT"})
            EXPECT_THAT(help, Not(HasSubstr(artefact))) << "mblab " << command << " --help";
    }
    const auto conform = run_mblab({"conform", "--help"}).out;
    EXPECT_THAT(conform, HasSubstr("--registers 1..65536"));
    EXPECT_THAT(conform, HasSubstr("--dut FILE"));
    EXPECT_THAT(run_mblab({"read", "--help"}).out, HasSubstr("--decode app|frame|bytes"));
}

TEST(CliEdges, ADashReportGoesToStandardOutputAlone) {
    TempDir dir;
    ChildProcess serve(serve_argv({}));
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    auto load = run_mblab({"load", target, "--duration", "1s", "--json", "-"});
    EXPECT_EQ(load.status, 0) << load.err;
    EXPECT_FALSE(nlohmann::json::parse(load.out, nullptr, false).is_discarded()) << load.out;
    EXPECT_FALSE(std::filesystem::exists(std::filesystem::current_path() / "-"));
    auto fuzz = run_mblab({"fuzz", target, "--cases", "20", "--rate", "0", "--json", "-",
                           "--reproducer", (dir / "finding.hex").string()});
    EXPECT_EQ(fuzz.status, 0) << fuzz.err;
    EXPECT_FALSE(nlohmann::json::parse(fuzz.out, nullptr, false).is_discarded()) << fuzz.out;
    EXPECT_THAT(fuzz.err, HasSubstr("no finding"));
}

TEST(CliEdges, AReportIsWrittenWholeOrNotAtAll) {
    TempDir dir;
    const auto report = dir / "report.json";
    // head closes the pipe after a line: conform dies of SIGPIPE long before its report is due.
    const auto ran = run_program(
        {"/bin/sh", "-c",
         std::string(MBLAB_BINARY) + " conform --json " + report.string() + " | head -n 1"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    if (std::filesystem::exists(report)) {
        EXPECT_FALSE(nlohmann::json::parse(file_text(report), nullptr, false).is_discarded());
    }
    // No temporary file is left beside it either.
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
        EXPECT_EQ(entry.path(), report) << "left behind: " << entry.path();
    // A refused run makes no file, and leaves an earlier report as it was.
    const auto fresh = dir / "fresh.json";
    EXPECT_EQ(run_mblab({"conform", "tcp://127.0.0.1:1", "--json", fresh.string()}).status, 2);
    EXPECT_FALSE(std::filesystem::exists(fresh));
    if (std::filesystem::exists(report)) {
        const auto before = file_text(report);
        run_mblab({"conform", "tcp://127.0.0.1:1", "--json", report.string()});
        EXPECT_EQ(file_text(report), before);
    }
}

}  // namespace
}  // namespace mblab::test
