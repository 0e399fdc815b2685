#include <gtest/gtest.h>

#include "conformance/judge.hpp"
#include "load/answer.hpp"
#include "support/hex.hpp"

namespace mblab::load {
namespace {

using test::hex;

AnswerPattern compiled(std::string_view text) {
    return AnswerPattern(conformance::ResolvedPattern{conformance::Pattern::parse(text)->tokens()});
}

std::optional<FailureKind> judged(std::vector<std::string_view> patterns, std::string_view frame) {
    std::vector<AnswerPattern> alternatives;
    for (auto text : patterns)
        alternatives.push_back(compiled(text));
    const auto bytes = hex(frame);
    return judge_answer(alternatives, bytes);
}

TEST(LoadAnswer, MatchesWithoutLookingAtTheTransactionId) {
    const auto read = compiled("00 00 00 00 00 05 01 03 02 XX XX");
    EXPECT_TRUE(read.matches(hex("12 34 00 00 00 05 01 03 02 AB CD")));
    EXPECT_FALSE(read.matches(hex("12 34 00 00 00 05 02 03 02 AB CD")));  // unit
    EXPECT_FALSE(read.matches(hex("12 34 00 00 00 05 01 03 02 AB")));     // short
    EXPECT_FALSE(read.matches(hex("12 34 00 00 00 05 01 03 02 AB CD EF")));
    EXPECT_FALSE(read.expects_exception());
    EXPECT_TRUE(compiled("00 00 00 00 00 03 01 83 02").expects_exception());
}

TEST(LoadAnswer, LengthFieldCountsWhatFollows) {
    const auto open = compiled("00 00 00 00 {len} 01 5B XX ...");
    EXPECT_TRUE(open.matches(hex("00 07 00 00 00 05 01 5B 09 00 00")));
    EXPECT_FALSE(open.matches(hex("00 07 00 00 00 06 01 5B 09 00 00")));
    EXPECT_FALSE(open.matches(hex("00 07 00 00 00 02 01 5B")));  // shorter than the pattern
    const auto fixed = compiled("00 00 00 00 {len} 01 10 00 10 00 01");
    EXPECT_TRUE(fixed.matches(hex("FF FF 00 00 00 06 01 10 00 10 00 01")));
    EXPECT_FALSE(fixed.matches(hex("FF FF 00 00 00 07 01 10 00 10 00 01")));
}

TEST(LoadAnswer, KindsOfFailure) {
    const std::string_view read = "00 00 00 00 00 05 01 03 02 XX XX";
    EXPECT_EQ(judged({read}, "00 09 00 00 00 05 01 03 02 00 00"), std::nullopt);
    EXPECT_EQ(judged({read}, "00 09 00 00 00 03 01 83 02"), FailureKind::UnexpectedException);
    EXPECT_EQ(judged({read}, "00 09 00 00 00 05 01 04 02 00 00"), FailureKind::WrongAnswer);
    EXPECT_EQ(judged({read}, "00 09 00 00 00 07 01 03 04 00 00 00 00"), FailureKind::WrongAnswer);
    // The byte count disagrees with the bytes that follow: the response does not decode.
    EXPECT_EQ(judged({read}, "00 09 00 00 00 05 01 03 03 00 00"), FailureKind::Malformed);
    EXPECT_EQ(judged({read}, "00 09 00 01 00 05 01 03 02 00 00"), FailureKind::Malformed);

    // An exception was expected: a different one is a wrong answer, not an unexpected one.
    const std::string_view exception = "00 00 00 00 00 03 01 83 03";
    EXPECT_EQ(judged({exception, "00 00 00 00 00 03 01 83 02"}, "00 01 00 00 00 03 01 83 02"),
              std::nullopt);
    EXPECT_EQ(judged({exception}, "00 01 00 00 00 03 01 83 04"), FailureKind::WrongAnswer);
    EXPECT_EQ(judged({exception}, "00 01 00 00 00 05 01 03 02 00 00"), FailureKind::WrongAnswer);
}

TEST(LoadAnswer, IllegalFunctionAnswer) {
    constexpr auto kIllegalFunction = protocol::ExceptionCode::IllegalFunction;
    const auto request = hex("00 00 00 00 00 06 01 14 00 00 00 01");
    EXPECT_TRUE(conformance::is_exception_answer(request, hex("00 03 00 00 00 03 01 94 01"),
                                                 kIllegalFunction));
    EXPECT_FALSE(conformance::is_exception_answer(request, hex("00 03 00 00 00 03 01 94 02"),
                                                  kIllegalFunction));
    EXPECT_FALSE(conformance::is_exception_answer(request, hex("00 03 00 00 00 03 01 83 01"),
                                                  kIllegalFunction));
}

TEST(LoadAnswer, KindNames) {
    EXPECT_EQ(failure_key(FailureKind::WrongAnswer), "wrong_answer");
    EXPECT_EQ(failure_key(FailureKind::UnexpectedException), "exception");
    EXPECT_EQ(failure_label(FailureKind::Dropped), "dropped connection");
}

}  // namespace
}  // namespace mblab::load
