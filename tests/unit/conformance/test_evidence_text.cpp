// The words and the bytes a vendor reads in a failure: the reason in words, long frames
// compacted, and evidence cut to a terminal's width without losing which byte differs.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "conformance/evidence_text.hpp"
#include "conformance/judge.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

using test::hex;

Exchange judged(const std::string& sent, const std::string& received, const std::string& expected) {
    auto pattern = Pattern::parse(expected);
    EXPECT_TRUE(pattern.ok()) << expected;
    return judge(hex(sent), {client::ReceiveStatus::Frame, hex(received)},
                 std::chrono::milliseconds(1000), {ResolvedPattern{pattern->tokens()}})
        .exchange;
}

TEST(FailureReason, DataWhereAnExceptionWasDueSaysSoWithTheCodeAndItsName) {
    const auto exchange = judged("00 01 00 00 00 06 01 03 FF FF 00 01",
                                 "00 01 00 00 00 05 01 03 02 12 34", "00 01 00 00 00 03 01 83 02");
    EXPECT_EQ(describe_failure(exchange),
              "answered with data where exception 02 (illegal data address) was expected");
}

TEST(FailureReason, DataWhereAnyExceptionWasDueSaysAnException) {
    const auto exchange = judged("00 01 00 00 00 02 01 2B", "00 01 00 00 00 03 01 2B 00",
                                 "00 01 00 00 00 03 01 AB XX");
    EXPECT_EQ(describe_failure(exchange), "answered with data where an exception was expected");
}

TEST(FailureReason, DataWhereAnExceptionWasDueNamesAWrongHeaderToo) {
    const auto exchange = judged("00 01 00 00 00 06 01 01 00 00 00 01",
                                 "00 07 00 00 00 04 01 01 01 00", "00 01 00 00 00 03 01 81 01");
    EXPECT_EQ(describe_failure(exchange),
              "answered with data where exception 01 (illegal function) was expected; also "
              "wrong transaction id");
}

TEST(FailureReason, AnExceptionWhereDataWasDueSaysSo) {
    const auto exchange = judged("00 01 00 00 00 06 01 03 00 00 00 01",
                                 "00 01 00 00 00 03 01 83 02", "00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(describe_failure(exchange),
              "exception 02 (illegal data address) where data was expected");
}

TEST(FailureReason, AnotherExceptionCodeNamesTheOneExpected) {
    const auto exchange = judged("00 01 00 00 00 06 01 03 00 00 00 00",
                                 "00 01 00 00 00 03 01 83 02", "00 01 00 00 00 03 01 83 03");
    EXPECT_EQ(describe_failure(exchange), "exception 02 (illegal data address) instead of 03");
}

TEST(FailureReason, AWrongFieldOfTheRightKindIsNamed) {
    const auto exchange =
        judged("00 01 00 00 00 06 01 03 00 00 00 01", "00 02 00 00 00 05 01 03 02 00 00",
               "00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(describe_failure(exchange), "wrong transaction id");
}

// On a line the notation's MBAP header was laid out by the tester: a longer answer is named by
// what the device sent (the byte count and the data), never as a wrong length field.
TEST(FailureReason, OnALineTheLaidOutHeaderIsNeverNamed) {
    const auto exchange =
        judged("00 01 00 00 00 06 01 03 00 00 00 01", "00 01 00 00 00 07 01 03 04 00 00 00 00",
               "00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(describe_failure(exchange).rfind("wrong length field, ", 0), 0U)
        << describe_failure(exchange);
    const auto on_line = describe_failure(exchange, client::Framing::Rtu);
    EXPECT_EQ(on_line.find("length field"), std::string::npos) << on_line;
    EXPECT_NE(on_line.find("byte count"), std::string::npos) << on_line;
    const auto other_id =
        judged("00 01 00 00 00 06 01 03 00 00 00 01", "00 02 00 00 00 05 01 03 02 00 00",
               "00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(describe_failure(other_id, client::Framing::Ascii), "wrong answer length");
}

TEST(CompactHex, ARunOfEightOrMoreIdenticalBytesIsOneCell) {
    std::vector<std::uint8_t> frame = hex("00 01 00 00 00 FD 01 03 FA");
    frame.insert(frame.end(), 246, 0x5A);
    frame.push_back(0x01);
    frame.insert(frame.end(), 7, 0x22);  // seven: not a run
    EXPECT_EQ(compact_hex(frame), "00 01 00 00 00 FD 01 03 FA 5A x246 01 22 22 22 22 22 22 22");
    EXPECT_EQ(compact_hex(hex("00 00 00 00 00 00 00 00")), "00 x8");
}

// A 250-byte answer where the pattern expects 2 bytes of data: the run of the answer is one cell
// in the received line, and the ^^ line marks it whole.
Exchange long_answer() {
    std::string received = "00 01 00 00 00 FD 01 03 FA";
    for (int i = 0; i < 250; ++i)
        received += " 5A";
    return judged("00 01 00 00 00 06 01 03 00 00 00 7D", received,
                  "00 01 00 00 00 05 01 03 02 XX XX");
}

TEST(EvidenceText, CompactsARunAndMarksItWhole) {
    const auto lines = evidence_lines(long_answer());
    ASSERT_EQ(lines.size(), 4U);
    EXPECT_EQ(lines[1], "received  00 01 00 00 00 FD 01 03 FA 5A 5A 5A x248");
    EXPECT_EQ(lines[2], "expected  00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(lines[3], "                         ^^       ^^       ^^^^^^^");
}

TEST(EvidenceText, TheLayoutGivesTheColumnsOfTheDifferingBytes) {
    const auto layout = evidence_layout(long_answer());
    using Span = std::pair<std::size_t, std::size_t>;
    EXPECT_EQ(layout[1].marked, (std::vector<Span>{{25, 27}, {34, 36}, {43, 50}}));
    EXPECT_EQ(layout[2].marked, (std::vector<Span>{{25, 27}, {34, 36}}));
}

// 60 distinct bytes where 2 were expected: the lines are cut between cells, the three lines of
// the comparison at the same columns, each piece labelled.
TEST(EvidenceText, WrapsAtTheWidthBetweenCellsKeepingTheMarksUnderTheirBytes) {
    std::string received = "00 01 00 00 00 3E 01 03 3C";
    for (int i = 0; i < 60; ++i)
        received += fmt::format(" {:02X}", i);
    const auto exchange =
        judged("00 01 00 00 00 06 01 03 00 00 00 1E", received, "00 01 00 00 00 05 01 03 02 XX XX");
    const auto lines = wrap_evidence(evidence_lines(exchange), 60);
    for (const auto& line : lines)
        EXPECT_LE(line.size(), 60U) << line;
    ASSERT_GE(lines.size(), 6U);
    EXPECT_EQ(lines[0], "sent      00 01 00 00 00 06 01 03 00 00 00 1E");
    EXPECT_EQ(lines[1], "received  00 01 00 00 00 3E 01 03 3C 00 01 02 03 04 05 06 07");
    EXPECT_EQ(lines[2], "expected  00 01 00 00 00 05 01 03 02 XX XX");
    EXPECT_EQ(lines[3], "                         ^^       ^^       ^^ ^^ ^^ ^^ ^^ ^^");
    EXPECT_EQ(lines[4], "received  08 09 0A 0B 0C 0D 0E 0F 10 11 12 13 14 15 16 17 18");
    EXPECT_EQ(lines[5], "          ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^ ^^");
    // Every received byte is still there, in order.
    std::string rejoined;
    for (const auto& line : lines) {
        if (line.starts_with("received  "))
            rejoined += (rejoined.empty() ? "" : " ") + line.substr(10);
    }
    EXPECT_EQ(rejoined, received);
}

TEST(EvidenceText, ALoneLongLineIsIndentedAfterItsFirstPiece) {
    const std::vector<std::string> lines = {
        "received  connection closed by peer: the server sent something rather long to say here"};
    EXPECT_EQ(wrap_evidence(lines, 40),
              (std::vector<std::string>{"received  connection closed by peer: the",
                                        "          server sent something rather",
                                        "          long to say here"}));
    EXPECT_EQ(wrap_evidence(lines, 0), lines);
}

CaseResult na(const std::string& id, const std::string& reason) {
    return {id, "[SEC] R-01", "a case", Outcome{Verdict::NotApplicable, reason, {}}};
}

TEST(SuiteInapplicable, IsEveryCaseNotApplicableForOneReason) {
    const std::vector<CaseResult> cases = {na("sec.1", "not over mbaps://"),
                                           na("sec.2", "not over mbaps://")};
    const auto why = suite_inapplicable("security", cases);
    ASSERT_TRUE(why);
    EXPECT_EQ(why->title, "all 2 cases of security");
    EXPECT_EQ(why->reason, "not over mbaps://");
}

TEST(SuiteInapplicable, IsNotASuiteThatAppliesInPartOrHasOneCase) {
    std::vector<CaseResult> cases = {na("sec.1", "not over mbaps://"),
                                     na("sec.2", "the DUT does not declare pki")};
    EXPECT_FALSE(suite_inapplicable("security", cases));
    cases[1] = na("sec.2", "not over mbaps://");
    cases[1].outcome.verdict = Verdict::Pass;
    EXPECT_FALSE(suite_inapplicable("security", cases));
    cases[1] = na("sec.2", "not over mbaps://");
    cases[1].interrupted = true;
    EXPECT_FALSE(suite_inapplicable("security", cases));
    EXPECT_FALSE(suite_inapplicable("security", std::span(cases).first(1)));
}

}  // namespace
}  // namespace mblab::conformance
