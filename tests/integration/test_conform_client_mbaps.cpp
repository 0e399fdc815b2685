#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "conform_client_support.hpp"
#include "support/temp_dir.hpp"

// `mblab conform-client --listen mbaps://`: the TCP scenarios behind TLS, and scenario 12, the
// server certificates a client must refuse, graded against `mblab read` and `openssl s_client`
// with and without its checks.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

std::vector<std::string> examiner(const std::vector<std::string>& more) {
    std::vector<std::string> argv = {MBLAB_BINARY,          "conform-client", "--listen",
                                     "mbaps://127.0.0.1:0", "--json",         "-"};
    argv.insert(argv.end(), more.begin(), more.end());
    return argv;
}

// openssl s_client sends one FC 03 request for registers 100..101 of unit 1 once it is
// connected; `checks` are the options that make it refuse what it cannot verify.
std::vector<std::string> s_client(const std::string& checks) {
    return {"--case",
            "tls.12",
            "--",
            "sh",
            "-c",
            "printf '\\000\\001\\000\\000\\000\\006\\001\\003\\000\\144\\000\\002' | openssl "
            "s_client -connect {host}:{port} -cert {cert} -key {key} -CAfile {ca} -quiet "
            "-no_ign_eof " +
                checks};
}

TEST(ConformClientMbaps, MblabReadPassesEveryScenarioBehindTlsAndRefusesEachCertificate) {
    const auto verdicts = client_verdicts(examiner({"--client-timeout",
                                                    "300ms",
                                                    "--client-retries",
                                                    "1",
                                                    "--",
                                                    MBLAB_BINARY,
                                                    "read",
                                                    "{url}",
                                                    "holding",
                                                    "{address}",
                                                    "{count}",
                                                    "--unit",
                                                    "{unit}",
                                                    "--timeout",
                                                    "300",
                                                    "--retries",
                                                    "1",
                                                    "--no-probe",
                                                    "--cert",
                                                    "{cert}",
                                                    "--key",
                                                    "{key}",
                                                    "--ca",
                                                    "{ca}"}));
    expect_verdicts(verdicts, 24U, {}, {"tcp.11"});
    EXPECT_THAT(verdicts.console,
                HasSubstr("tls.12.1  an expired server certificate is refused  (refused the "
                          "handshake: sslv3 alert certificate expired)"));
    EXPECT_THAT(verdicts.console, HasSubstr("(refused the handshake: tlsv1 alert unknown ca)"));
    EXPECT_THAT(verdicts.console,
                HasSubstr("(refused the handshake: sslv3 alert bad certificate)"));
    // The PKI made for the run is gone with it.
    const auto at = verdicts.console.find("PKI: ");
    ASSERT_NE(at, std::string::npos) << verdicts.console;
    const auto dir = verdicts.console.substr(at + 5, verdicts.console.find(' ', at + 5) - at - 5);
    EXPECT_THAT(dir, HasSubstr("mblab-conform-client-pki-"));
    EXPECT_FALSE(std::filesystem::exists(dir)) << dir;
}

TEST(ConformClientMbaps, OpensslThatChecksTheCertificatePasses) {
    const auto verdicts =
        client_verdicts(examiner(s_client("-verify_return_error -verify_ip {host}")));
    expect_verdicts(verdicts, 3U, {}, {});
    EXPECT_THAT(verdicts.console, HasSubstr("(refused the handshake: tlsv1 alert unknown ca)"));
}

TEST(ConformClientMbaps, OpensslThatGoesOnRegardlessFailsEachWithTheRequestItSent) {
    const auto verdicts = client_verdicts(examiner(s_client("")));
    expect_verdicts(verdicts, 3U, {"tls.12.1", "tls.12.2", "tls.12.3"}, {});
    for (const char* flaw :
         {"that has expired", "from an unknown CA", "naming wrong-name.invalid only"}) {
        EXPECT_THAT(verdicts.console,
                    HasSubstr(std::string("took a server certificate ") + flaw +
                              ": sent 00 01 00 00 00 06 01 03 00 64 00 02 inside the session"));
    }
}

TEST(ConformClientMbaps, APkiFromMblabPkiIsPresentedAndAnIncompleteOneRefused) {
    TempDir dir;
    const auto pki = (dir.path() / "pki").string();
    ASSERT_EQ(run_program({MBLAB_BINARY, "pki", pki}).status, 0);
    const auto verdicts = client_verdicts(
        examiner({"--pki", pki, "--case", "tls.12", "--", MBLAB_BINARY, "read", "{url}", "holding",
                  "{address}", "--cert", "{cert}", "--key", "{key}", "--ca", "{ca}"}));
    expect_verdicts(verdicts, 3U, {}, {});
    EXPECT_THAT(verdicts.console, HasSubstr("PKI: " + pki + " ({ca} ca.pem"));
    EXPECT_TRUE(std::filesystem::exists(pki + "/ca.pem"));  // a given PKI is left as it was

    std::filesystem::remove(pki + "/server-wrong-name.pem");
    const auto incomplete = run_program(examiner({"--pki", pki, "--", "true"}));
    EXPECT_EQ(incomplete.status, 2);
    EXPECT_THAT(incomplete.err,
                HasSubstr("--pki " + pki + ": --cert " + pki + "/server-wrong-name.pem"));
    const auto plain = run_program({MBLAB_BINARY, "conform-client", "--pki", pki, "--", "true"});
    EXPECT_EQ(plain.status, 2);
    EXPECT_THAT(plain.err, HasSubstr("--pki is for an mbaps:// --listen"));
}

}  // namespace
}  // namespace mblab::test
