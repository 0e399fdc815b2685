#include <gtest/gtest.h>

#include <string>

#include "framer_driver.hpp"
#include "protocol/ascii_framer.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using namespace mblab::test;

std::vector<std::uint8_t> chars(std::string_view text) {
    return {text.begin(), text.end()};
}

std::vector<Seen> run(std::string_view text) {
    const auto bytes = chars(text);
    return run_all_chunkings(AsciiFramer{}, bytes);
}

Seen ascii_frame(std::string_view text, std::string_view pdu_hex, unsigned unit) {
    return test::frame(to_hex(chars(text)), pdu_hex, unit);
}

Seen error(std::string text, std::string_view adu = "", unsigned unit = 0) {
    Seen out;
    out.status = FrameStatus::Error;
    out.error = std::move(text);
    out.adu = to_hex(chars(adu));
    out.unit = unit;
    return out;
}

constexpr std::string_view kSpecFrame = ":1103006B00037E\r\n";

TEST(AsciiFramer, ExampleOfTheSerialSpec) {
    const auto events = run(kSpecFrame);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

// [SER 2.5.2]: hex digits are 0-9 and A-F; the rest of a frame with a lower-case one is lost.
TEST(AsciiFramer, LowercaseHexIsAFramingError) {
    const auto events = run(std::string(":1103006b00037e\r\n") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0],
              error("lower-case hex digit 'b' at position 8 (only 0-9 and A-F are allowed)"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

// The tester reads such a frame and says what was wrong with it.
TEST(AsciiFramer, LenientReadsLowercaseHexAsAViolation) {
    AsciiFramer framer(true);
    const auto bytes = chars(":1103006b00037e\r\n");
    std::size_t consumed = 0;
    const auto event = framer.feed(bytes, consumed);
    ASSERT_TRUE(event.is_frame());
    EXPECT_EQ(to_hex(event.pdu), "03 00 6B 00 03");
    EXPECT_STREQ(event.violation,
                 "lower-case hex digit at position 8 (only 0-9 and A-F are allowed)");
}

TEST(AsciiFramer, GarbageBetweenFramesIsSkipped) {
    const auto events =
        run(std::string("\r\nxx") + std::string(kSpecFrame) + std::string("\n\0junk", 6) +
            ":0103000000 0AF2\r\n" + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
    EXPECT_EQ(events[1], error("non-hex character 0x20 at position 11"));
    EXPECT_EQ(events[2], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, SeveralFramesBackToBack) {
    const auto events = run(":01030000000AF2\r\n:1103006B00037E\r\n:F7070200\r\n");
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0], ascii_frame(":01030000000AF2\r\n", "03 00 00 00 0A", 0x01));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
    EXPECT_EQ(events[2], ascii_frame(":F7070200\r\n", "07 02", 0xF7));
}

// [SER 2.5.2] noise on a line: each bad frame is dropped and the next good one is still found.
TEST(AsciiFramer, OddNumberOfHexDigits) {
    const auto events = run(std::string(":1103006B00037\r\n") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("odd number of hex digits (13)", ":1103006B00037\r\n"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, NonHexCharacterDropsTheRestOfTheFrame) {
    const auto events = run(std::string(":11030G6B00037E\r\n") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("non-hex character 0x47 at position 6"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, BadLrc) {
    const auto events = run(std::string(":1103006B00037F\r\n") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0],
              error("LRC mismatch: frame has 0x7F, computed 0x7E", ":1103006B00037F\r\n", 0x11));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, FrameUnderThreeBytes) {
    const auto events = run(":01FF\r\n:\r\n");
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("frame under 3 bytes (2 decoded)", ":01FF\r\n"));
    EXPECT_EQ(events[1], error("frame under 3 bytes (0 decoded)", ":\r\n"));
}

TEST(AsciiFramer, ColonInsideAFrameStartsANewOne) {
    const auto events = run(std::string(":110300") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("frame interrupted by ':' after 7 characters"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, CrNotFollowedByLf) {
    const auto events = run(std::string(":1103006B00037E\rX") + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("CR followed by 0x58 instead of 0x0A"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

// A 253-byte PDU makes the longest frame: 1 + 2 * 255 + 2 = 513 characters.
std::string longest_frame(std::size_t pdu_size) {
    std::string text = ":01";
    unsigned sum = 0x01;
    for (std::size_t i = 0; i < pdu_size; ++i) {
        text += "41";
        sum += 0x41;
    }
    static constexpr char kDigits[] = "0123456789ABCDEF";
    const unsigned lrc = (0x100 - sum % 0x100) % 0x100;
    text += kDigits[lrc >> 4];
    text += kDigits[lrc & 0xF];
    return text + "\r\n";
}

TEST(AsciiFramer, FrameOf513CharactersIsTheLongest) {
    const std::string text = longest_frame(253);
    ASSERT_EQ(text.size(), 513U);
    const auto events = run(text);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].status, FrameStatus::Frame);
    EXPECT_EQ(events[0].pdu, to_hex(std::vector<std::uint8_t>(253, 0x41)));
}

TEST(AsciiFramer, OverLengthIsAnErrorThenResynchronises) {
    const std::string text = longest_frame(254);
    ASSERT_EQ(text.size(), 515U);
    const auto events = run(text + std::string(kSpecFrame));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("frame over 513 characters"));
    EXPECT_EQ(events[1], ascii_frame(kSpecFrame, "03 00 6B 00 03", 0x11));
}

TEST(AsciiFramer, EndDelimiterCanBeChanged) {
    AsciiFramer framer;
    framer.set_end_delimiter('!');
    const auto events = run_all_chunkings(
        framer, chars(std::string(":1103006B00037E\r!") + std::string(kSpecFrame)));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], ascii_frame(":1103006B00037E\r!", "03 00 6B 00 03", 0x11));
    EXPECT_EQ(events[1], error("CR followed by 0x0A instead of 0x21"));
}

TEST(AsciiFramer, TimeoutDropsAnUnfinishedFrame) {
    AsciiFramer framer;
    const auto part = chars(":110300");
    std::size_t consumed = 0;
    EXPECT_EQ(framer.feed(part, consumed).status, FrameStatus::NeedMore);
    EXPECT_TRUE(framer.has_partial());
    const FrameEvent event = framer.on_silence();
    EXPECT_EQ(event.status, FrameStatus::Error);
    EXPECT_STREQ(event.error, "incomplete frame: timeout after 7 characters");
    EXPECT_FALSE(framer.has_partial());
    EXPECT_EQ(framer.on_silence().status, FrameStatus::NeedMore);
}

TEST(AsciiFramer, AFrameStoppingAfterItsCrLacksItsLf) {
    AsciiFramer framer;
    const auto part = chars(":1103006B00037E\r");
    std::size_t consumed = 0;
    EXPECT_EQ(framer.feed(part, consumed).status, FrameStatus::NeedMore);
    const FrameEvent event = framer.on_silence();
    EXPECT_EQ(event.status, FrameStatus::Error);
    EXPECT_STREQ(event.error, "incomplete frame: CR not followed by 0x0A (LF) after 16 characters");
}

TEST(AsciiFramer, ResetDropsThePartialFrame) {
    AsciiFramer framer;
    std::size_t consumed = 0;
    (void)framer.feed(chars(":1103"), consumed);
    framer.reset();
    EXPECT_FALSE(framer.has_partial());
    EXPECT_EQ(framer.feed(chars("006B00037E\r\n"), consumed).status, FrameStatus::NeedMore);
}

}  // namespace
}  // namespace mblab::protocol
