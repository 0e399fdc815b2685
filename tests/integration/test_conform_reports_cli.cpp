#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
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
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: --json " + json + ": cannot write the report: directory " +
                           (dir / "no-such-dir").string() + " does not exist\n");
    EXPECT_EQ(ran.out, "");
    EXPECT_FALSE(fs::exists(dir / "no-such-dir"));
}

TEST(ConformReportsCli, AReportUnderAFileOrOnADirectoryIsRefused) {
    test::TempDir dir;
    const std::string file = (dir / "plain").string();
    std::ofstream(file) << "x";
    const std::string pcap = file + "/capture.pcap";
    auto ran = mblab({"conform", unreachable(), "--pcap", pcap});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: --pcap " + pcap + ": cannot write the report: " + file +
                           " is not a directory\n");

    ran = mblab({"conform", unreachable(), "--junit", dir.path().string()});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: --junit " + dir.path().string() +
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
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err,
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
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: cannot connect to " + target + ": connection refused\n");
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

}  // namespace
}  // namespace mblab::conformance
