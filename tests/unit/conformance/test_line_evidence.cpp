// A case judged in the catalogue's MBAP notation shows, once laid out for its line, the frames
// that crossed the line: hex in, hex (or ASCII text) out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "conformance/evidence_text.hpp"
#include "conformance/judge.hpp"
#include "conformance/line_evidence.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

using test::hex;

class NoFacts : public FactSource {
  public:
    std::optional<std::vector<std::uint8_t>> fact(std::string_view) const override {
        return std::nullopt;
    }
};

std::vector<std::uint8_t> text(std::string_view chars) {
    return {chars.begin(), chars.end()};
}

// The exchange a case judged: `sent` and the answer in the notation, against `expect`.
Exchange judged(std::string_view sent, std::string_view answer, std::string_view expect) {
    auto pattern = resolve(Pattern::parse(expect).value(), NoFacts{});
    client::Received received{client::ReceiveStatus::Frame, hex(answer)};
    return judge(hex(sent), std::move(received), std::chrono::milliseconds(1000), {pattern.value()})
        .exchange;
}

constexpr std::string_view kRead = "00 2A 00 00 00 06 01 03 00 00 00 01";
constexpr std::string_view kAnswer = "00 2A 00 00 00 05 01 03 02 12 34";
constexpr std::string_view kException = "00 2A 00 00 {len} 01 83 02";

// The read of kRead answered kAnswer where kException was due, laid out for a line in `framing`
// that carried `request` and `answer`.
Exchange failed_on_line(client::Framing framing, const std::vector<std::uint8_t>& request,
                        const std::vector<std::uint8_t>& answer) {
    LineFrames frames;
    frames.note(hex(kRead), request);
    frames.note(hex(kAnswer), answer);
    Exchange exchange = judged(kRead, kAnswer, kException);
    show_as_on_line(exchange, framing, frames);
    return exchange;
}

TEST(LineEvidence, AnRtuExchangeShowsAddressPduAndCrcLowByteFirst) {
    const Exchange exchange = failed_on_line(client::Framing::Rtu, hex("01 03 00 00 00 01 84 0A"),
                                             hex("01 03 02 12 34 B5 33"));
    EXPECT_EQ(exchange.framing, client::Framing::Rtu);
    EXPECT_EQ(exchange.sent, hex("01 03 00 00 00 01 84 0A"));
    EXPECT_EQ(exchange.received, hex("01 03 02 12 34 B5 33"));
    // The expected frame without the MBAP header, with its CRC 0xF1C0 low byte first.
    EXPECT_EQ(exchange.expected, "01 83 02 C0 F1");
    EXPECT_EQ(exchange.match.differs, (std::vector<std::size_t>{1, 3, 4, 5, 6}));
    EXPECT_EQ(evidence_lines(exchange),
              (std::vector<std::string>{
                  "sent      01 03 00 00 00 01 84 0A", "received  01 03 02 12 34 B5 33",
                  "expected  01 83 02 C0 F1", "             ^^    ^^ ^^ ^^ ^^"}));
}

TEST(LineEvidence, AnAsciiExchangeShowsItsText) {
    const Exchange exchange = failed_on_line(client::Framing::Ascii, text(":010300000001FB\r\n"),
                                             text(":0103021234B4\r\n"));
    EXPECT_EQ(exchange.received, text(":0103021234B4\r\n"));
    // Bytes 1 (the function code) and 3 (the LRC where 12 came) differ, 4 and 5 came too many.
    EXPECT_EQ(exchange.match.differs, (std::vector<std::size_t>{1, 3, 4, 5}));
    EXPECT_EQ(evidence_lines(exchange),
              (std::vector<std::string>{R"(sent      :010300000001FB\r\n)",
                                        R"(received  :0103021234B4\r\n)",
                                        R"(expected  :0183027A\r\n)", "             ^^  ^^^^^^"}));
}

TEST(LineEvidence, AnExpectedFrameWithWildcardsHasAnyCrc) {
    LineFrames frames;
    frames.note(hex(kAnswer), hex("01 03 02 12 34 B5 33"));
    Exchange exchange = judged(kRead, kAnswer, "00 2A 00 00 {len} 01 03 02 XX XX");
    show_as_on_line(exchange, client::Framing::Rtu, frames);
    EXPECT_EQ(exchange.expected, "01 03 02 XX XX XX XX");
    EXPECT_TRUE(exchange.match.differs.empty());
    // A request the line never carried (not noted) stays as it was.
    EXPECT_EQ(exchange.sent, hex(kRead));
}

TEST(LineEvidence, BytesThatCameAsTheyWereStayAndModbusTcpIsLeftAlone) {
    Exchange unasked =
        unasked_exchange({client::ReceiveStatus::Frame, hex("01 03 02 12 34 B5 33")}, {});
    show_as_on_line(unasked, client::Framing::Rtu, LineFrames{});
    EXPECT_EQ(unasked.received, hex("01 03 02 12 34 B5 33"));
    EXPECT_EQ(unasked.framing, client::Framing::Rtu);

    LineFrames frames;
    frames.note(hex(kRead), hex("01 03 00 00 00 01 84 0A"));
    Exchange tcp = judged(kRead, kAnswer, kException);
    const Exchange before = tcp;
    show_as_on_line(tcp, client::Framing::Mbap, frames);
    EXPECT_EQ(tcp.sent, before.sent);
    EXPECT_EQ(tcp.expected, before.expected);
    EXPECT_EQ(tcp.match.differs, before.match.differs);
}

TEST(LineEvidence, AsciiTextWritesWhatIsNotPrintable) {
    EXPECT_EQ(frame_text(client::Framing::Ascii, text(":01\x7F\\\r\n")), R"(:01\x7F\\\r\n)");
    EXPECT_EQ(frame_text(client::Framing::Rtu, hex("01 83 02 C0 F1")), "01 83 02 C0 F1");
    // Byte 2 of an ASCII frame sits after ':' and two bytes' digits; of an RTU one after two cells.
    EXPECT_EQ(frame_column(client::Framing::Ascii, 2), 5U);
    EXPECT_EQ(frame_column(client::Framing::Rtu, 2), 6U);
    EXPECT_EQ(frame_cells(client::Framing::Ascii, text(":0103021234B4\r\n")), 6U);
    EXPECT_EQ(frame_cells(client::Framing::Ascii, text("0103")), 0U);
}

// A sweep on a line sends tens of thousands of frames: the last ones are kept, not all.
TEST(LineEvidence, OnlyTheLastFramesAreKept) {
    LineFrames frames;
    for (std::size_t i = 0; i <= LineFrames::kKept; ++i) {
        const std::vector<std::uint8_t> notation{static_cast<std::uint8_t>(i >> 8),
                                                 static_cast<std::uint8_t>(i)};
        frames.note(notation, notation);
    }
    EXPECT_EQ(frames.size(), LineFrames::kKept);
    EXPECT_EQ(frames.wire_of(std::vector<std::uint8_t>{0, 0}), nullptr);
    const std::vector<std::uint8_t> last{static_cast<std::uint8_t>(LineFrames::kKept >> 8),
                                         static_cast<std::uint8_t>(LineFrames::kKept)};
    ASSERT_NE(frames.wire_of(last), nullptr);
    EXPECT_EQ(*frames.wire_of(last), last);
}

}  // namespace
}  // namespace mblab::conformance
