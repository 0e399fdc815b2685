#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "conformance/client_judge.hpp"
#include "support/hex.hpp"

// The verdicts of conform-client from what the examiner saw and what the client printed.
namespace mblab::conformance {
namespace {

using namespace std::chrono_literals;
using test::hex;
using ::testing::HasSubstr;

const char* kRequest = "00 01 00 00 00 06 01 03 00 64 00 02";

ClientCase scenario(ClientScenario which, std::uint8_t code = 0) {
    for (const auto& c : client_tcp_cases())
        if (c.scenario == which && c.exception == code) return c;
    return {};
}

ClientDeclarations declared(unsigned retries = 1) {
    ClientDeclarations d;
    d.timeout = 300ms;
    d.retries = retries;
    return d;
}

// The examiner of `which` after requests at the times given (ms), all on one connection.
ClientExaminer examined(ClientScenario which, const ClientDeclarations& d,
                        std::initializer_list<int> at, std::uint8_t code = 0) {
    const auto zero = ClientExaminer::Clock::time_point{};
    ClientExaminer exam(scenario(which, code), d, zero);
    const auto c = exam.opened(zero);
    for (const int ms : at) {
        exam.received(c, hex(kRequest), zero + std::chrono::milliseconds(ms));
        exam.due(zero + std::chrono::milliseconds(ms + 100));
    }
    return exam;
}

ClientRun ran(int status, std::string output, std::chrono::milliseconds elapsed = 100ms) {
    return {status, false, std::move(output), elapsed, 3600ms};
}

TEST(ClientJudge, ADecoyInTheOutputFailsWithTheBytesItCameFrom) {
    const auto d = declared();
    const auto exam = examined(ClientScenario::WrongTransaction, d, {0});
    const auto outcome = judge_client(exam, d, ran(0, "40100 40101\n"));
    EXPECT_EQ(outcome.verdict, Verdict::Fail);
    EXPECT_THAT(outcome.reason,
                HasSubstr("took the decoy 40100 from 5A 5B 00 00 00 07 01 03 04 9C A4 9C A5"));
    EXPECT_EQ(judge_client(exam, d, ran(0, "10100 10101\n")).verdict, Verdict::Pass);
    EXPECT_EQ(judge_client(exam, d, ran(1, "bad transaction id\n")).verdict, Verdict::Fail);
}

// openssl s_client prints the answer's bytes as they came: the reason shows them as escapes,
// and stays valid UTF-8 (a JSON report of such a run once failed to be written at all).
TEST(ClientJudge, BytesTheClientPrintedRawAreQuotedAsEscapes) {
    const auto d = declared();
    const auto exam = examined(ClientScenario::WrongTransaction, d, {0});
    constexpr char kRaw[] =
        "40100 40101\n\0\x01\x9C\xA4"
        "DONE\n";
    const auto outcome = judge_client(exam, d, ran(0, std::string(kRaw, sizeof kRaw - 1)));
    EXPECT_EQ(outcome.verdict, Verdict::Fail);
    EXPECT_THAT(outcome.reason, HasSubstr(R"(output: "40100 40101 \x00\x01\x9C\xA4DONE")"));
    const auto long_output = judge_client(exam, d, ran(0, "40100 " + std::string(400, '\xFF')));
    EXPECT_THAT(long_output.reason, HasSubstr(R"(\xFF\xFF...")"));
    EXPECT_LT(long_output.reason.size(), 400U);
}

TEST(ClientJudge, HexValuesCountToo) {
    const auto d = declared();
    const auto exam = examined(ClientScenario::WrongUnit, d, {0});
    EXPECT_EQ(judge_client(exam, d, ran(0, "[100]: 0x9CA4\n")).verdict, Verdict::Fail);
    EXPECT_EQ(judge_client(exam, d, ran(0, "0x2774 0x2775")).verdict, Verdict::Pass);
}

TEST(ClientJudge, AnExceptionReportedAsSuccessFails) {
    const auto d = declared();
    const auto exam = examined(ClientScenario::Exception, d, {0}, 0x06);
    const auto zero = judge_client(exam, d, ran(0, "0 0\n"));
    EXPECT_EQ(zero.verdict, Verdict::Fail);
    EXPECT_THAT(zero.reason, HasSubstr("exception 06 reported as success"));
    const auto error = judge_client(exam, d, ran(1, "exception 06\n"));
    EXPECT_EQ(error.verdict, Verdict::Pass);
    EXPECT_EQ(error.reason, "an error naming the code");
}

// libmodbus and mbpoll print the exception's name, not its number: that names the code too.
TEST(ClientJudge, AnExceptionNamedInWordsIsNamed) {
    const auto d = declared();
    const auto reason = [&](std::uint8_t code, const char* output) {
        return judge_client(examined(ClientScenario::Exception, d, {0}, code), d, ran(1, output))
            .reason;
    };
    EXPECT_EQ(reason(0x02, "error: Illegal data address\n"), "an error naming the code");
    EXPECT_EQ(reason(0x04, "Slave device or server failure"), "an error naming the code");
    EXPECT_EQ(reason(0x0B, "error: Target device failed to respond"), "an error naming the code");
    EXPECT_EQ(reason(0x06, "SLAVE DEVICE OR SERVER IS BUSY"), "an error naming the code");
    // Another code's name is not this one's.
    EXPECT_EQ(reason(0x05, "error: Negative acknowledge"),
              "an error (its output does not name the code)");
    EXPECT_EQ(reason(0x03, "error: Illegal data address"),
              "an error (its output does not name the code)");
    EXPECT_EQ(reason(0x06, "error: no answer"), "an error (its output does not name the code)");
}

TEST(ClientJudge, AnErrorPatternStandsForTheExitStatus) {
    auto d = declared();
    d.error_pattern = "^ERR";
    const auto exam = examined(ClientScenario::Exception, d, {0}, 0x02);
    EXPECT_EQ(judge_client(exam, d, ran(0, "ERR 2\n")).verdict, Verdict::Pass);
    EXPECT_EQ(judge_client(exam, d, ran(1, "2\n")).verdict, Verdict::Fail);
}

TEST(ClientJudge, OnlyBusyCodesMayBeAskedAgain) {
    const auto d = declared();
    EXPECT_EQ(
        judge_client(examined(ClientScenario::Exception, d, {0, 10}, 0x02), d, ran(1, "e")).verdict,
        Verdict::Fail);
    EXPECT_EQ(
        judge_client(examined(ClientScenario::Exception, d, {0, 10}, 0x06), d, ran(1, "e")).verdict,
        Verdict::Pass);
}

TEST(ClientJudge, NoReplyCountsTheTriesAndTheirSpacing) {
    const auto d = declared(1);
    EXPECT_EQ(
        judge_client(examined(ClientScenario::NoReply, d, {0, 300}), d, ran(1, "", 700ms)).verdict,
        Verdict::Pass);
    const auto storm =
        judge_client(examined(ClientScenario::NoReply, d, {0, 300, 600}), d, ran(1, "", 1000ms));
    EXPECT_THAT(storm.reason, HasSubstr("sent 3 requests where 1 retries make 2: a resend storm"));
    const auto early =
        judge_client(examined(ClientScenario::NoReply, d, {0, 50}), d, ran(1, "", 400ms));
    EXPECT_THAT(early.reason, HasSubstr("resent after 50 ms, before its 300 ms timeout ran out"));
    auto stuck = ran(137, "", 3600ms);
    stuck.stopped = true;
    EXPECT_THAT(judge_client(examined(ClientScenario::NoReply, d, {0, 300}), d, stuck).reason,
                HasSubstr("it never timed out"));
}

TEST(ClientJudge, MissingDeclarationsAreNotApplicable) {
    ClientDeclarations none;
    const auto exam = examined(ClientScenario::NoReply, none, {0});
    const auto outcome = judge_client(exam, none, ran(1, ""));
    EXPECT_EQ(outcome.verdict, Verdict::NotApplicable);
    EXPECT_EQ(outcome.reason, "the client's timeout is not declared (--client-timeout)");
    EXPECT_EQ(undeclared(scenario(ClientScenario::LateReply), declared(0))->reason,
              "needs --client-retries 1 or more: the stale answer must meet a later request");
    EXPECT_TRUE(undeclared(scenario(ClientScenario::Pipelined), declared())) << "pipelining";
}

TEST(ClientJudge, NoRequestAtAllFails) {
    const auto d = declared();
    ClientExaminer exam(scenario(ClientScenario::SplitAnswer), d, {});
    const auto outcome = judge_client(exam, d, ran(127, "cannot run 'x'"));
    EXPECT_EQ(outcome.verdict, Verdict::Fail);
    EXPECT_THAT(outcome.reason, HasSubstr("sent no request to unit 1 (exit status 127)"));
}

ClientCase untrusted() {
    for (const auto& c : client_mbaps_cases())
        if (c.scenario == ClientScenario::Untrusted) return c;
    return {};
}

// SEC R-06: the client must not go on past a certificate it cannot verify. One that does is
// answered with decoys, and the request it sent is the evidence.
TEST(ClientJudge, ARequestBehindAnUntrustedCertificateFailsARefusalPasses) {
    const auto d = declared();
    const auto zero = ClientExaminer::Clock::time_point{};
    ClientExaminer took(untrusted(), d, zero);
    const auto c = took.opened(zero);
    took.received(c, hex(kRequest), zero);
    const auto answered = took.due(zero);
    ASSERT_EQ(answered.size(), 1U);
    EXPECT_EQ(answered[0].bytes, hex("00 01 00 00 00 07 01 03 04 9C A4 9C A5"));
    const auto failed = judge_client(took, d, ran(0, "40100 40101\n"));
    EXPECT_EQ(failed.verdict, Verdict::Fail);
    EXPECT_THAT(failed.reason, HasSubstr("took a server certificate that has expired: sent 00 01 "
                                         "00 00 00 06 01 03 00 64 00 02 inside the session and "
                                         "showed the decoy 40100"));

    ClientExaminer refused(untrusted(), d, zero);
    refused.refused(refused.opened(zero), "sslv3 alert certificate expired");
    const auto passed = judge_client(refused, d, ran(1, "certificate verify failed\n"));
    EXPECT_EQ(passed.verdict, Verdict::Pass);
    EXPECT_EQ(passed.reason, "refused the handshake: sslv3 alert certificate expired");
    EXPECT_EQ(judge_client(refused, d, ran(0, "")).verdict, Verdict::Fail);
    ClientRun hung = ran(137, "");
    hung.stopped = true;
    EXPECT_EQ(judge_client(refused, d, hung).verdict, Verdict::Fail);
}

}  // namespace
}  // namespace mblab::conformance
