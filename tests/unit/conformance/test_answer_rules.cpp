#include <gtest/gtest.h>

#include "conformance/answer_rules.hpp"
#include "support/hex.hpp"

// The spec's rules for an answer's fields, PDU in, verdict out.
namespace mblab::conformance {
namespace {

using test::hex;

std::optional<std::string> broken(const char* request, const char* answer) {
    return answer_rule_broken(hex(request), hex(answer));
}

TEST(AnswerRules, ReadCoilsPadBitsMustBeZero) {
    EXPECT_EQ(broken("01 00 00 00 03", "01 01 05"), std::nullopt);
    auto set = broken("01 00 00 00 03", "01 01 0D");
    ASSERT_TRUE(set);
    EXPECT_NE(set->find("unused bits of the last data byte: 0D"), std::string::npos) << *set;
    EXPECT_EQ(broken("02 00 00 00 10", "02 02 FF FF"), std::nullopt);  // whole bytes: no pad
}

TEST(AnswerRules, DecoderAndEchoFailuresNameTheField) {
    auto count = broken("03 00 00 00 02", "03 02 00 01");
    ASSERT_TRUE(count);
    EXPECT_NE(count->find("register"), std::string::npos) << *count;
    EXPECT_EQ(broken("03 00 00 00 01", "83 02"), std::nullopt);  // exceptions: by pattern
    EXPECT_EQ(broken("03 00 00 00 00", "03 00"), std::nullopt);  // a broken request: ditto
}

// Device identification answers: 2B 0E code level more-follows next-id count, then id / length /
// value triples.
TEST(AnswerRules, DeviceIdStreamsThatAreRight) {
    // Basic stream from 00, all in one answer.
    EXPECT_EQ(broken("2B 0E 01 00", "2B 0E 01 81 00 00 03 00 01 41 01 01 42 02 01 43"),
              std::nullopt);
    // More follows, next object id past the last one sent.
    EXPECT_EQ(broken("2B 0E 01 00", "2B 0E 01 81 FF 01 01 00 01 41"), std::nullopt);
    // A regular stream that serves its own category only, starting past the object asked for.
    EXPECT_EQ(broken("2B 0E 02 00", "2B 0E 02 82 00 00 01 03 01 55"), std::nullopt);
    // An unknown object asked for: the stream starts over at 00.
    EXPECT_EQ(broken("2B 0E 01 50", "2B 0E 01 81 00 00 01 00 01 41"), std::nullopt);
}

TEST(AnswerRules, DeviceIdFieldsThatAreWrong) {
    struct Wrong {
        const char* request;
        const char* answer;
        const char* words;
    };
    const Wrong wrong[] = {
        {"2B 0E 02 00", "2B 0E 02 81 00 00 02 00 01 41 03 01 55",
         "object 03 is beyond conformity level 81"},
        {"2B 0E 01 00", "2B 0E 01 83 00 00 02 00 01 41 05 01 55", "answers a basic stream request"},
        {"2B 0E 01 00", "2B 0E 01 81 00 00 02 01 01 41 00 01 55", "out of order"},
        {"2B 0E 01 02", "2B 0E 01 81 00 00 01 01 01 41", "the first object is 01"},
        {"2B 0E 01 00", "2B 0E 01 81 00 05 01 00 01 41",
         "next object id is 05 with more follows 00"},
        {"2B 0E 01 00", "2B 0E 01 81 FF 00 01 00 01 41", "it must name an object after"},
        {"2B 0E 04 01", "2B 0E 04 01 00 00 01 01 01 41", "declares stream access only"},
        {"2B 0E 04 01", "2B 0E 04 81 00 00 01 02 01 41", "object id is 0x02, expected 0x01"},
        {"2B 0E 01 00", "2B 0E 01 81 00 00 01 00 09 41", "object length"},
    };
    for (const auto& w : wrong) {
        auto why = broken(w.request, w.answer);
        ASSERT_TRUE(why) << w.answer;
        EXPECT_NE(why->find(w.words), std::string::npos) << w.answer << ": " << *why;
    }
}

}  // namespace
}  // namespace mblab::conformance
