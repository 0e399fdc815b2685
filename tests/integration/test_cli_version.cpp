// `mblab --version` and `-V`: what a bug report or a report's reader needs to find the build.
#include <gtest/gtest.h>

#include <regex>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

TEST(CliVersion, BothFlagsPrintTheVersionAndTheCommit) {
    // The commit is the one checked out when the build was configured, which other commits may
    // have followed since: its form is checked, not its value.
    const std::regex expected(std::string("mblab ") + MBLAB_VERSION +
                              R"( \(commit ([0-9a-f]{7,40}|unknown)\)\n)");
    for (const char* flag : {"--version", "-V"}) {
        auto ran = run_mblab({flag});
        EXPECT_EQ(ran.status, 0) << flag;
        EXPECT_TRUE(std::regex_match(ran.out, expected)) << flag << ": " << ran.out;
        EXPECT_EQ(ran.err, "") << flag;
    }
}

}  // namespace
}  // namespace mblab::test
