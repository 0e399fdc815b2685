// Usage errors from argument parsing: one line on stderr naming the command, exit status 2.
#include <gtest/gtest.h>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

TEST(CliUsage, AMissingArgumentNamesTheCommand) {
    auto ran = run_mblab({"read"});
    expect_failed(ran, 2, "mblab read: target is required (run 'mblab read --help' for usage)\n");
    EXPECT_EQ(ran.out, "");
}

TEST(CliUsage, AnUnknownOptionNamesTheCommand) {
    auto ran = run_mblab({"conform", "--bogus"});
    expect_failed(ran, 2,
                  "mblab conform: The following argument was not expected: --bogus (run 'mblab "
                  "conform --help' for usage)\n");
}

TEST(CliUsage, AnUnknownCommandListsTheCommands) {
    auto ran = run_mblab({"frobnicate", "x"});
    expect_failed(
        ran, 2,
        "mblab: unknown command 'frobnicate' (commands: conform, conform-client, serve, read, "
        "write, diag, devid, raw, watch, load, pki, fuzz, profile, scan, sunspec)\n");
    auto none = run_mblab({});
    expect_failed(none, 2,
                  "mblab: a command is required: conform, conform-client, serve, read, write, "
                  "diag, devid, raw, watch, load, pki, fuzz, profile, scan, sunspec (run 'mblab "
                  "--help' for usage)\n");
}

// conform and conform-client write the same four report files; each help names what its run
// judges one by one.
TEST(CliUsage, BothConformCommandsOfferTheFourReportFiles) {
    for (const auto& [command, item] :
         {std::pair{"conform", "case"}, {"conform-client", "scenario"}}) {
        const auto help = run_mblab({command, "--help"});
        ASSERT_EQ(help.status, 0) << command;
        for (const char* option : {"--json", "--junit", "--html", "--pcap"})
            EXPECT_NE(help.out.find(option), std::string::npos) << command << " " << option;
        EXPECT_NE(help.out.find(std::string("one test case per ") + item), std::string::npos)
            << help.out;
        EXPECT_NE(help.out.find(std::string("comment its ") + item + "'s id"), std::string::npos)
            << help.out;
    }
}

// conform and load pick suites and cases one way (SuiteOptions), and write their text reports one
// way (TextReports): their help says the same of both.
TEST(CliUsage, ConformAndLoadChooseCasesAndWriteReportsAlike) {
    for (const char* command : {"conform", "load"}) {
        const auto help = run_mblab({command, "--help"});
        ASSERT_EQ(help.status, 0) << command;
        for (const char* text :
             {"--suite", "--catalogue", "--case", "'7.5.*' (* any text, ? any one character)",
              "with the cases they depend on",
              "('-': standard output, the console report then "
              "going to standard error)"}) {
            EXPECT_NE(help.out.find(text), std::string::npos) << command << ": " << text;
        }
    }
    EXPECT_NE(run_mblab({"load", "--help"}).out.find("one test case per node"), std::string::npos);
}

}  // namespace
}  // namespace mblab::test
