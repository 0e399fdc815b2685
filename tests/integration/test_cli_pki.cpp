// `mblab pki`: what the command prints and refuses; the certificates themselves are checked in
// tests/unit/security/test_pki.cpp and, with the openssl CLI, in tests/interop/test_pki_openssl.sh.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <string>

#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

TEST(CliPki, WritesTheFilesListsThemAndSaysWhatToRunNext) {
    TempDir dir;
    const std::string pki = (dir / "lab").string();
    auto ran = run_mblab({"pki", pki, "--role", "Operator"});
    ASSERT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.err, "");
    EXPECT_NE(ran.out.find(pki + "/ca.pem\n" + pki + "/ca.key\n"), std::string::npos) << ran.out;
    EXPECT_NE(ran.out.find(pki + "/client-Operator.pem\n"), std::string::npos) << ran.out;
    EXPECT_NE(ran.out.find("  mblab serve --listen mbaps://127.0.0.1:8802 --cert " + pki +
                           "/server.pem --key " + pki + "/server.key --ca " + pki + "/ca.pem"),
              std::string::npos)
        << ran.out;
    EXPECT_NE(ran.out.find("--cert " + pki + "/client-Operator.pem"), std::string::npos);
    // 2 files for each of 13 certificates (3 of them the server certificates a client must
    // refuse), one line each, then 3 lines of next:.
    EXPECT_EQ(std::count(ran.out.begin(), ran.out.end(), '\n'), 29);
    EXPECT_NE(ran.out.find(pki + "/server-wrong-name.pem\n"), std::string::npos) << ran.out;
    struct stat status {};
    ASSERT_EQ(::stat((dir / "lab/client-Operator.key").c_str(), &status), 0);
    EXPECT_EQ(status.st_mode & 0777U, 0600U);
}

TEST(CliPki, ASecondRunNeedsForce) {
    TempDir dir;
    const std::string pki = (dir / "lab").string();
    ASSERT_EQ(run_mblab({"pki", pki, "--role", "Operator"}).status, 0);
    auto again = run_mblab({"pki", pki, "--role", "Operator"});
    EXPECT_EQ(again.status, 2);
    EXPECT_EQ(again.out, "");
    EXPECT_EQ(again.err,
              "mblab pki: " + pki + "/ca.pem exists already; --force replaces the files\n");
    EXPECT_EQ(run_mblab({"pki", pki, "--role", "Operator", "--force"}).status, 0);
}

TEST(CliPki, BadArgumentsAreOneLineAndExit2) {
    TempDir dir;
    const std::string pki = (dir / "lab").string();
    auto slash = run_mblab({"pki", pki, "--role", "a/b"});
    expect_failed(slash, 2,
                  "mblab pki: role 'a/b' contains '/' (it names the file client-ROLE.pem)\n");
    auto days = run_mblab({"pki", pki, "--days", "0"});
    EXPECT_EQ(days.status, 2);
    EXPECT_EQ(std::count(days.err.begin(), days.err.end(), '\n'), 1) << days.err;
    auto key = run_mblab({"pki", pki, "--key-type", "dsa"});
    EXPECT_EQ(key.status, 2);
    EXPECT_EQ(std::count(key.err.begin(), key.err.end(), '\n'), 1) << key.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "lab"));
}

}  // namespace
}  // namespace mblab::test
