#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "load_cli_support.hpp"
#include "support/ports.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

// `--html FILE` of conform and load as a user meets it: the page written by a run, and a file
// that cannot be written refused before any traffic with one line. The page in a real browser is
// tests/browser/check_reports.py.
namespace mblab::test {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(HtmlReportsCli, ConformWritesEveryCaseOfTheJsonReport) {
    TempDir dir;
    const std::string html = (dir / "report.html").string();
    const std::string json = (dir / "report.json").string();
    auto ran = run_mblab({"conform", "--case", "7.5.*", "--html", html, "--json", json});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    const std::string page = file_text(html);
    const auto report = nlohmann::json::parse(file_text(json));
    std::size_t cases = 0;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"]) {
            const std::string id = c["id"];
            const std::string verdict = c["verdict"];
            EXPECT_TRUE(has(page, "data-verdict=\"" + verdict + "\" data-id=\"" + id + "\"")) << id;
            ++cases;
        }
    }
    EXPECT_GT(cases, 0U);
    EXPECT_TRUE(has(page, "PASSED: no case failed"));
    // The built-in device identified itself, and the provenance names the command line.
    EXPECT_TRUE(
        has(page, "<tr><th>vendor name (object 00)</th><td>" +
                      report["provenance"]["device_identity"]["vendor_name"].get<std::string>() +
                      "</td></tr>"));
    EXPECT_TRUE(has(page, "--case &apos;7.5.*&apos; --html"));
}

// The example the README and docs/catalogue.md print, run as printed (build/mblab being the
// binary under test) in a directory of its own.
TEST(HtmlReportsCli, TheDocumentedExampleWorksAsPrinted) {
    const std::string example = "build/mblab conform --html report.html";
    for (const char* doc : {"README.md", "docs/catalogue.md"}) {
        EXPECT_TRUE(has(file_text(fs::path(MBLAB_SOURCE_DIR) / doc), "\n" + example + "\n")) << doc;
    }
    TempDir dir;
    auto ran = run_program({"/bin/sh", "-c",
                            "cd '" + dir.path().string() + "' && '" + MBLAB_BINARY + "'" +
                                example.substr(std::string("build/mblab").size())});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_TRUE(file_text(dir / "report.html").starts_with("<!DOCTYPE html>"));
}

TEST(HtmlReportsCli, ConformRefusesAnUnwritablePageBeforeConnecting) {
    TempDir dir;
    const std::string html = (dir / "no-such-dir" / "report.html").string();
    auto ran = run_mblab({"conform", tcp_target(closed_port()), "--html", html});
    expect_failed(ran, 2,
                  "mblab conform: --html " + html + ": cannot write the report: directory " +
                      (dir / "no-such-dir").string() + " does not exist\n");
    EXPECT_EQ(ran.out, "");

    const std::string same = (dir / "report").string();
    ran = run_mblab({"conform", tcp_target(closed_port()), "--json", same, "--html", same});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err, "mblab conform: --html " + same +
                           ": the same file as --json; each report needs its own file\n");
    EXPECT_FALSE(fs::exists(same));
}

TEST(HtmlReportsCli, LoadWritesANodeTableAndALatencyChart) {
    Device device;
    const std::string html = temp("load.html");
    auto run = mblab_load("html",
                          {device.url(), "--duration", "1s", "--connections", "1", "--html", html});
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    const std::string page = slurp(html);
    EXPECT_TRUE(has(page, "<tr class=\"node\"><td>" + device.url() + "</td>"));
    EXPECT_TRUE(has(page, "<svg class=\"histogram\""));
    EXPECT_TRUE(has(page, "<rect class=\"bar\""));
    EXPECT_TRUE(has(page, "<p class=\"banner PASS\" id=\"outcome\">PASS</p>"));
}

// Load checks its report files before it connects, so the plan is not even printed.
TEST(HtmlReportsCli, LoadRefusesAnUnwritablePageBeforeAnyTraffic) {
    Device device;
    TempDir dir;
    const std::string html = (dir / "no-such-dir" / "load.html").string();
    auto ran = run_mblab({"load", device.url(), "--duration", "1s", "--html", html});
    expect_failed(ran, 2,
                  "mblab load: --html " + html + ": cannot write the report: directory " +
                      (dir / "no-such-dir").string() + " does not exist\n");
    EXPECT_EQ(ran.out, "");
}

}  // namespace
}  // namespace mblab::test
