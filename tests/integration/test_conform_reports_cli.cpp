#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "support/ports.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

// `mblab conform` report files, case selection and interruption as a user meets them: exit
// statuses, the one line of a refusal, the files left behind.
namespace mblab::conformance {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

using test::Ran;

Ran mblab(const std::vector<std::string>& args) {
    return test::run_mblab(args);
}

// A target nothing listens on: a run that got as far as connecting would say so instead.
std::string unreachable() {
    return test::tcp_target(test::closed_port());
}

TEST(ConformReportsCli, AReportInAMissingDirectoryIsRefusedBeforeConnecting) {
    test::TempDir dir;
    const std::string json = (dir / "no-such-dir" / "report.json").string();
    auto ran = mblab({"conform", unreachable(), "--json", json});
    expect_failed(ran, 2,
                  "mblab conform: --json " + json + ": cannot write the report: directory " +
                      (dir / "no-such-dir").string() + " does not exist\n");
    EXPECT_EQ(ran.out, "");
    EXPECT_FALSE(fs::exists(dir / "no-such-dir"));
}

// `-` is standard output: the report alone there (the console report on standard error), and no
// file named `-` left in the working directory.
TEST(ConformReportsCli, AReportToStandardOutput) {
    test::TempDir dir;
    const auto in_dir = [&](const std::string& args) {
        return test::run_program(
            {"/bin/sh", "-c",
             "cd " + dir.path().string() + " && " MBLAB_BINARY " conform " + args});
    };
    auto ran = in_dir("--case 7.3.1 --json -");
    EXPECT_EQ(ran.status, 0) << ran.err;
    const auto report = nlohmann::json::parse(ran.out, nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << ran.out;
    EXPECT_EQ(report["passed"], true) << ran.out;
    EXPECT_THAT(ran.err, HasSubstr("PASS     7.3.1"));
    EXPECT_FALSE(fs::exists(dir / "-"));
    ran = in_dir("--case 7.3.1 --junit -");
    EXPECT_EQ(ran.status, 0);
    EXPECT_EQ(ran.out.rfind("<?xml", 0), 0U) << ran.out;
    ran = in_dir("--case 7.3.1 --json - --html -");
    expect_failed(ran, 2, "mblab conform: only one report can go to standard output (-)\n");
    ran = in_dir("--case 7.3.1 --pcap -");
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err,
              "mblab conform: --pcap -: a capture is binary; give it a file (tshark -r FILE "
              "reads it)\n");
    EXPECT_FALSE(fs::exists(dir / "-"));
}

TEST(ConformReportsCli, AReportUnderAFileOrOnADirectoryIsRefused) {
    test::TempDir dir;
    const std::string file = (dir / "plain").string();
    std::ofstream(file) << "x";
    const std::string pcap = file + "/capture.pcap";
    auto ran = mblab({"conform", unreachable(), "--pcap", pcap});
    expect_failed(ran, 2,
                  "mblab conform: --pcap " + pcap + ": cannot write the report: " + file +
                      " is not a directory\n");

    ran = mblab({"conform", unreachable(), "--junit", dir.path().string()});
    expect_failed(ran, 2,
                  "mblab conform: --junit " + dir.path().string() +
                      ": cannot write the report: it is a directory\n");
    EXPECT_EQ(ran.out, "");
}

TEST(ConformReportsCli, AReportInADirectoryWithoutWritePermissionIsRefused) {
    if (::geteuid() == 0) GTEST_SKIP() << "root writes in any directory";
    test::TempDir dir;
    const fs::path locked = dir / "locked";
    fs::create_directory(locked);
    ::chmod(locked.c_str(), 0555);
    const std::string junit = (locked / "report.xml").string();
    auto ran = mblab({"conform", unreachable(), "--junit", junit});
    ::chmod(locked.c_str(), 0755);
    expect_failed(
        ran, 2,
        "mblab conform: --junit " + junit + ": cannot write the report: permission denied\n");
}

TEST(ConformReportsCli, TwoReportsInOneFileAreRefused) {
    test::TempDir dir;
    const std::string path = (dir / "report").string();
    auto ran = mblab({"conform", unreachable(), "--json", path, "--junit", path});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: --junit " + path +
                           ": the same file as --json; each report needs its own file\n");
    EXPECT_FALSE(fs::exists(path));
}

TEST(ConformReportsCli, ARunThatFailsToStartLeavesNoEmptyReportAndKeepsAnOldOne) {
    test::TempDir dir;
    const std::string json = (dir / "new.json").string();
    const std::string junit = (dir / "old.xml").string();
    std::ofstream(junit) << "<old/>\n";
    const std::string target = unreachable();
    auto ran = mblab({"conform", target, "--json", json, "--junit", junit});
    expect_failed(ran, 2, "mblab conform: cannot connect to " + target + ": connection refused\n");
    EXPECT_FALSE(fs::exists(json));
    EXPECT_EQ(test::file_text(junit), "<old/>\n");
}

TEST(ConformReportsCli, ACheckedReportIsWrittenByTheRun) {
    test::TempDir dir;
    const std::string json = (dir / "report.json").string();
    auto ran = mblab({"conform", "--suite", "mbap", "--json", json});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(test::file_text(json).find("\"tool\": \"mblab conform\""), std::string::npos);
}

std::vector<std::string> case_ids(const nlohmann::json& report) {
    std::vector<std::string> ids;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"])
            ids.push_back(c["id"]);
    }
    return ids;
}

TEST(ConformReportsCli, CaseRunsOnlyTheMatchingCasesAndWhatTheyDependOn) {
    test::TempDir dir;
    const std::string json = (dir / "cases.json").string();
    auto ran = mblab(
        {"conform", "--case", "7.5.*", "--case", "7.13.2", "--case", "mbap.?", "--json", json});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    const auto report = nlohmann::json::parse(test::file_text(json));
    // 7.13.2 depends on 7.5.1, which the pattern 7.5.* takes anyway; mbap.? leaves out mbap.10.
    EXPECT_EQ(case_ids(report), (std::vector<std::string>{"7.5.1", "7.5.2", "7.13.2", "mbap.1",
                                                          "mbap.2", "mbap.3", "mbap.4", "mbap.5",
                                                          "mbap.6", "mbap.7", "mbap.8", "mbap.9"}));
    EXPECT_EQ(report["summary"]["total"], 12);
    EXPECT_EQ(ran.out.find("device-id"), std::string::npos) << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("  PASS     7.13.2  Alternate encoding"));
}

TEST(ConformReportsCli, ACaseBringsTheCasesItDependsOn) {
    auto ran = mblab({"conform", "--list", "--suite", "policy-2.1", "--case", "7.13.2"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out,
                HasSubstr("\n  7.5.1   Function 0x03 read multiple registers  (CTP 7.5.1)\n"
                          "  7.13.2  Alternate encoding"));
    EXPECT_EQ(ran.out.find("9.1.1"), std::string::npos) << ran.out;
}

TEST(ConformReportsCli, ACasePatternThatMatchesNothingIsRefusedBeforeConnecting) {
    auto ran = mblab({"conform", unreachable(), "--suite", "policy-2.1", "--suite", "mbap",
                      "--case", "7.5.1", "--case", "9.9.*"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err,
              "mblab conform: --case '9.9.*' matches no case of the selected suites (policy-2.1, "
              "mbap); conform --list shows the case ids\n");
    EXPECT_EQ(ran.out, "");
}

TEST(ConformReportsCli, ProfileTakesAShippedProfileByName) {
    auto ran = mblab({"conform", "--profile", "multi-unit", "--case", "9.1.1"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("(declared by profile multi-unit.toml)\n"));
    EXPECT_THAT(ran.out, HasSubstr("  PASS     9.1.1"));
}

TEST(ConformReportsCli, AnUnknownProfileNameListsTheShippedOnes) {
    auto ran = mblab({"conform", "--profile", "no-such-profile"});
    expect_failed(ran, 2,
                  "mblab conform: --profile: no profile file or shipped profile named "
                  "'no-such-profile' (shipped: access-ranges, moving, multi-unit, "
                  "reference, rs485-instrument, sunspec-inverter)\n");
    EXPECT_EQ(ran.out, "");
}

// Starts a run slowed by a long --settle, waits for its first case line, sends `signal_number`
// and collects the rest.
Ran interrupt_run(int signal_number, const std::string& json, const std::string& junit,
                  const std::string& html) {
    test::ChildProcess child({MBLAB_BINARY, "conform", "--settle", "300", "--json", json, "--junit",
                              junit, "--html", html});
    Ran ran;
    while (auto line = child.read_stdout_line(std::chrono::seconds(60))) {
        ran.out += *line + "\n";
        if (line->starts_with("  PASS")) break;
    }
    child.signal(signal_number);
    while (auto line = child.read_stdout_line(std::chrono::seconds(60)))
        ran.out += *line + "\n";
    ran.status = child.wait_exit(std::chrono::seconds(60)).value_or(-1);
    ran.err = child.drain_stderr();
    return ran;
}

void expect_interrupted_reports(const Ran& ran, const std::string& json, const std::string& junit,
                                const std::string& html) {
    const auto report = nlohmann::json::parse(test::file_text(json));
    EXPECT_EQ(report["interrupted"], true);
    EXPECT_EQ(report["passed"], false);
    std::size_t run = 0;
    std::size_t left = 0;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"]) {
            if (c["reason"] == "interrupted") {
                EXPECT_EQ(c["verdict"], "NOT RUN");
                ++left;
            } else {
                ++run;
            }
        }
    }
    EXPECT_GE(run, 1U);
    EXPECT_GE(left, 1U);
    EXPECT_EQ(report["summary"]["total"], run + left);
    // An interrupted run is not kept waiting for the device to identify itself.
    EXPECT_EQ(report["provenance"]["device_identity"]["reason"],
              "not asked: the run was interrupted");
    const std::string xml = test::file_text(junit);
    EXPECT_THAT(xml, HasSubstr("<skipped message=\"interrupted\"/>"));
    EXPECT_NE(test::file_text(html).find(fmt::format(
                  "INTERRUPTED: the run was interrupted after {} of {} cases", run, run + left)),
              std::string::npos);
    EXPECT_NE(ran.out.find(fmt::format("Interrupted: {} of {} cases run; the reports mark the "
                                       "other {} NOT RUN (interrupted)\n",
                                       run, run + left, left)),
              std::string::npos)
        << ran.out;
}

TEST(ConformReportsCli, SigintStopsBetweenCasesWritesTheReportsAndExits130) {
    test::TempDir dir;
    const std::string json = (dir / "int.json").string();
    const std::string junit = (dir / "int.xml").string();
    const std::string html = (dir / "int.html").string();
    auto ran = interrupt_run(SIGINT, json, junit, html);
    EXPECT_EQ(ran.status, 130) << ran.out << ran.err;
    expect_interrupted_reports(ran, json, junit, html);
}

TEST(ConformReportsCli, SigtermStopsTheSameWayAndExits143) {
    test::TempDir dir;
    const std::string json = (dir / "term.json").string();
    const std::string junit = (dir / "term.xml").string();
    const std::string html = (dir / "term.html").string();
    auto ran = interrupt_run(SIGTERM, json, junit, html);
    EXPECT_EQ(ran.status, 143) << ran.out << ran.err;
    expect_interrupted_reports(ran, json, junit, html);
}

}  // namespace
}  // namespace mblab::conformance
