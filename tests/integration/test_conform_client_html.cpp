#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "child_process.hpp"
#include "conform_client_support.hpp"
#include "support/temp_dir.hpp"
#include "support/temp_path.hpp"

// `mblab conform-client --html`: a page of the client under test, its scenarios' verdicts and
// citations, and what the wire carried in each, the decoy a failing client took marked.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::vector<std::string> wrong_unit_client(const std::string& html) {
    std::vector<std::string> argv = {
        MBLAB_BINARY, "conform-client", "--client-timeout", "300ms",    "--client-retries", "1",
        "--case",     "tcp.4",          "--case",           "tcp.6.02", "--html",           html,
        "--"};
    const auto client = python_client(1, "wrong-unit");
    argv.insert(argv.end(), client.begin(), client.end());
    return argv;
}

TEST(ConformClientHtml, ThePageIsOfTheClientWithEachScenariosWire) {
    const auto html = temp_path("conform-client.html");
    const auto ran = run_program(wrong_unit_client(html));
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    const auto page = file_text(html);
    EXPECT_THAT(page, HasSubstr("<h1>mblab conform-client tcp://127.0.0.1:"));
    EXPECT_THAT(page, HasSubstr("<h2>Client under test</h2>"));
    EXPECT_THAT(page, Not(HasSubstr("Device under test")));
    EXPECT_THAT(page, HasSubstr("<tr><th>timeout</th><td>300 ms</td></tr>"));
    EXPECT_THAT(page, HasSubstr("data-verdict=\"FAIL\" data-id=\"tcp.4\""));
    EXPECT_THAT(page, HasSubstr("data-verdict=\"PASS\" data-id=\"tcp.6.02\""));
    EXPECT_THAT(page, HasSubstr(">TCPG 3.1.3</a>"));
    // The failure's wire open, the decoy from unit 2 marked; the pass's folded.
    EXPECT_THAT(page, HasSubstr("<details class=\"wire\" open><summary>what the wire carried (3 "
                                "frames)</summary>"));
    EXPECT_THAT(page, HasSubstr("client    00 01 00 00 00 06 01 03 00 64 00 02\n"));
    EXPECT_THAT(page, HasSubstr("examiner  <mark class=\"diff\">00 01 00 00 00 07 02 03 04 9C A4 "
                                "9C A5</mark>  (decoy)\n"));
    EXPECT_THAT(page, HasSubstr("<details class=\"wire\"><summary>what the wire carried (2 "
                                "frames)</summary>"));
}

TEST(ConformClientHtml, ADashWritesThePageToStandardOutputAndTheConsoleToStandardError) {
    const auto ran = run_program(wrong_unit_client("-"));
    EXPECT_EQ(ran.status, 1);
    EXPECT_THAT(ran.out, HasSubstr("<!DOCTYPE html>"));
    EXPECT_THAT(ran.out, Not(HasSubstr("Summary:")));
    EXPECT_THAT(ran.err, HasSubstr("Summary: 1 passed, 1 failed"));
}

}  // namespace
}  // namespace mblab::test
