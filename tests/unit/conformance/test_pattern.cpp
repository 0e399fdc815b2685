#include <gtest/gtest.h>

#include "conformance/pattern.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

using test::hex;

class Facts : public FactSource {
  public:
    std::optional<std::vector<std::uint8_t>> fact(std::string_view name) const override {
        if (name == "unit") return std::vector<std::uint8_t>{0x11};
        if (name == "address") return std::vector<std::uint8_t>{0x12, 0x34};
        return std::nullopt;
    }
};

ResolvedPattern resolved(std::string_view text) {
    auto pattern = Pattern::parse(text);
    EXPECT_TRUE(pattern.ok()) << text;
    auto out = resolve(pattern.value(), Facts{});
    EXPECT_TRUE(out.ok()) << text;
    return out.value();
}

TEST(Pattern, RendersARequestWithFactsAndComputedLength) {
    auto request = resolved("00 00 00 00 {len} {unit} 03 {address} 00 01");
    EXPECT_EQ(render_bytes(request), hex("00 00 00 00 00 06 11 03 12 34 00 01"));
}

TEST(Pattern, AcceptsGluedBytesAndRepeats) {
    auto request = resolved("0000 0000 {len} {unit} 0F 0000 0010 02 FF*2");
    EXPECT_EQ(render_bytes(request), hex("00 00 00 00 00 09 11 0F 00 00 00 10 02 FF FF"));
    EXPECT_EQ(to_text(resolved("01 XX*3 ...")), "01 XX XX XX ...");
}

TEST(Pattern, ParseErrorsNameColumnAndReason) {
    struct Bad {
        const char* text;
        std::size_t column;
        const char* reason;
    };
    const Bad cases[] = {
        {"00 0G", 4, "'0G': expected hex bytes, XX, {placeholder} or ..."},
        {"00 123", 4, "'123': hex bytes are written as pairs of digits"},
        {"00 {unit", 4, "'{unit': a placeholder ends with '}'"},
        {"00 {Unit}", 4, "'{Unit}': a placeholder name is lower-case letters, digits and '_'"},
        {"00 ... 01", 8, "'01': nothing may follow '...'"},
        {"XX*0", 1, "'XX': a repeat is one byte or XX, '*', and a count from 1 to 260"},
        {"   ", 1, "the pattern is empty"},
    };
    for (const auto& bad : cases) {
        auto parsed = Pattern::parse(bad.text);
        ASSERT_FALSE(parsed.ok()) << bad.text;
        EXPECT_EQ(parsed.error().column, bad.column) << bad.text;
        EXPECT_EQ(parsed.error().reason, bad.reason) << bad.text;
    }
}

TEST(Pattern, MissingFactIsNamed) {
    auto pattern = Pattern::parse("00 {fifo_address}");
    ASSERT_TRUE(pattern.ok());
    auto out = resolve(pattern.value(), Facts{});
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().name, "fifo_address");
}

TEST(Pattern, ConcreteMeansNoWildcards) {
    EXPECT_TRUE(Pattern::parse("00 {len} {unit}")->is_concrete());
    EXPECT_FALSE(Pattern::parse("00 XX")->is_concrete());
    EXPECT_FALSE(Pattern::parse("00 ...")->is_concrete());
}

TEST(Match, ExactAnswerMatches) {
    auto result =
        match(resolved("00 00 00 00 00 04 {unit} 01 01 XX"), hex("00 00 00 00 00 04 11 01 01 5A"));
    EXPECT_TRUE(result.matched);
    EXPECT_TRUE(result.differs.empty());
}

TEST(Match, MarksEachDifferingByte) {
    auto result =
        match(resolved("00 00 00 00 00 04 {unit} 01 01 XX"), hex("00 01 00 00 00 04 12 01 01 5A"));
    EXPECT_FALSE(result.matched);
    EXPECT_EQ(result.differs, (std::vector<std::size_t>{1, 6}));
    EXPECT_EQ(result.expected_cells, (std::vector<std::string>{"00", "00", "00", "00", "00", "04",
                                                               "11", "01", "01", "XX"}));
}

TEST(Match, MarksMissingAndExtraBytes) {
    auto pattern = resolved("00 00 00 00 00 05 {unit} 03 02 XX XX");
    auto short_answer = match(pattern, hex("00 00 00 00 00 05 11 03 02 00"));
    EXPECT_EQ(short_answer.differs, (std::vector<std::size_t>{10}));
    auto long_answer = match(pattern, hex("00 00 00 00 00 05 11 03 02 00 00 00"));
    EXPECT_EQ(long_answer.differs, (std::vector<std::size_t>{11}));
}

TEST(Match, LengthPlaceholderMustAgreeWithTheFrame) {
    auto pattern = resolved("00 00 00 00 {len} {unit} 5B XX ...");
    EXPECT_TRUE(match(pattern, hex("00 00 00 00 00 05 11 5B 01 02 03")).matched);
    auto wrong = match(pattern, hex("00 00 00 00 00 06 11 5B 01 02 03"));
    EXPECT_EQ(wrong.differs, (std::vector<std::size_t>{5}));
    EXPECT_EQ(wrong.expected_cells[5], "05");
    // Without "...", {len} is what the pattern describes, whatever came.
    auto fixed = match(resolved("00 00 00 00 {len} {unit} 03 02 XX XX"),
                       hex("00 00 00 00 00 04 11 03 02 00"));
    EXPECT_EQ(fixed.expected_cells[5], "05");
    EXPECT_EQ(fixed.differs, (std::vector<std::size_t>{5, 10}));
}

TEST(Match, RestAcceptsNothingMore) {
    EXPECT_TRUE(match(resolved("01 02 ..."), hex("01 02")).matched);
    EXPECT_FALSE(match(resolved("01 02 XX ..."), hex("01 02")).matched);
}

}  // namespace
}  // namespace mblab::conformance
