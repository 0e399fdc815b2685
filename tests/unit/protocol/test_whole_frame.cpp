#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/adu.hpp"
#include "protocol/framer.hpp"
#include "protocol/mbap_header.hpp"
#include "support/hex.hpp"

// One whole frame in a buffer (a frame a reader already cut, one sent, one in a log): its header
// and PDU or why the bytes are no such frame, in each framing. Hex in, header and PDU out.
namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;

std::vector<std::uint8_t> chars(std::string_view text) {
    return {text.begin(), text.end()};
}

// "unit 0x11 tid 0x0001 pid 0x0000 length 6 pdu [03 00 6B 00 03]", or the error.
std::string shown(const Result<Adu, const char*>& adu) {
    if (!adu) return std::string("error: ") + adu.error();
    const auto& h = adu->header;
    char head[96];
    if (h.has_transaction()) {
        std::snprintf(head, sizeof head, "unit 0x%02X tid 0x%04X pid 0x%04X length %u", h.unit,
                      unsigned{h.transaction_id}, unsigned{h.protocol_id}, unsigned{h.length});
    } else {
        std::snprintf(head, sizeof head, "%s unit 0x%02X", framing_name(h.framing), h.unit);
    }
    return std::string(head) + " pdu [" + to_hex(adu->pdu) + "]";
}

std::string whole(Framing framing, const std::vector<std::uint8_t>& bytes) {
    Framer framer({framing});
    return shown(framer.whole_frame(bytes));
}

TEST(WholeFrame, MbapGivesTheHeaderFieldsAndAViewOfThePdu) {
    const auto bytes = hex("00 01 00 00 00 06 11 03 00 6B 00 03");
    EXPECT_EQ(whole(Framing::Mbap, bytes),
              "unit 0x11 tid 0x0001 pid 0x0000 length 6 pdu [03 00 6B 00 03]");
    Framer framer({Framing::Mbap});
    const auto adu = framer.whole_frame(bytes);
    ASSERT_TRUE(adu);
    EXPECT_EQ(adu->pdu.data(), bytes.data() + 7) << "an MBAP PDU is a view, not a copy";
}

TEST(WholeFrame, MbapHeaderAloneHasAnEmptyPduForTheCallerToJudge) {
    EXPECT_EQ(whole(Framing::Mbap, hex("00 08 00 00 00 01 11")),
              "unit 0x11 tid 0x0008 pid 0x0000 length 1 pdu []");
}

TEST(WholeFrame, MalformedMbap) {
    EXPECT_EQ(whole(Framing::Mbap, hex("00 01 00 00 00 06")),
              "error: the frame is 6 bytes long, shorter than an MBAP header (7)");
    EXPECT_EQ(whole(Framing::Mbap, hex("00 07 00 01 00 06 11 03 00 6B 00 03")),
              "error: MBAP protocol id is 0x0001, expected 0x0000 (Modbus)");
    // One byte missing, one too many, and two frames back to back.
    EXPECT_EQ(whole(Framing::Mbap, hex("00 01 00 00 00 06 11 03 00 6B 00")),
              "error: MBAP length 6 disagrees with the 5 bytes after it");
    EXPECT_EQ(whole(Framing::Mbap, hex("00 01 00 00 00 06 11 03 00 6B 00 03 FF")),
              "error: MBAP length 6 disagrees with the 7 bytes after it");
    EXPECT_EQ(whole(Framing::Mbap, hex("00 01 00 00 00 02 11 07 00 02 00 00 00 02 11 07")),
              "error: MBAP length 2 disagrees with the 10 bytes after it");
    EXPECT_EQ(whole(Framing::Mbap, hex("00 01 00 00 00 00 11")),
              "error: MBAP length 0 disagrees with the 1 bytes after it");
}

TEST(WholeFrame, RtuChecksTheCrcOverTheWholeFrame) {
    // [SER 2.5.1.2]: the CRC's low byte first.
    EXPECT_EQ(whole(Framing::Rtu, hex("11 03 00 6B 00 03 76 87")),
              "RTU unit 0x11 pdu [03 00 6B 00 03]");
    std::array<std::uint8_t, 8> address_alone{};
    const auto size = write_adu({Framing::Rtu, 0x07}, {}, address_alone);
    ASSERT_EQ(size, 3U);
    EXPECT_EQ(whole(Framing::Rtu, {address_alone.begin(), address_alone.begin() + 3}),
              "RTU unit 0x07 pdu []");
}

TEST(WholeFrame, MalformedRtu) {
    EXPECT_EQ(whole(Framing::Rtu, hex("11 03")),
              "error: the frame is 2 bytes long, too short for RTU");
    EXPECT_EQ(whole(Framing::Rtu, hex("11 03 00 6B 00 03 87 76")),
              "error: the RTU frame's CRC does not match");
    // A frame with a byte more: the CRC no longer sits at the end.
    EXPECT_EQ(whole(Framing::Rtu, hex("11 03 00 6B 00 03 76 87 FF")),
              "error: the RTU frame's CRC does not match");
}

TEST(WholeFrame, AsciiDecodesTheHex) {
    // [SER 2.5.2.2]: the example frame, LRC 7E.
    EXPECT_EQ(whole(Framing::Ascii, chars(":1103006B00037E\r\n")),
              "ASCII unit 0x11 pdu [03 00 6B 00 03]");
}

TEST(WholeFrame, MalformedAscii) {
    EXPECT_EQ(whole(Framing::Ascii, chars(":1103006B00030E\r\n")),
              "error: the ASCII frame is broken: LRC mismatch: frame has 0x0E, computed 0x7E");
    EXPECT_EQ(whole(Framing::Ascii, chars(":1103006G00037E\r\n")),
              "error: the ASCII frame is broken: non-hex character 0x47 at position 8");
    EXPECT_EQ(whole(Framing::Ascii, chars(":1103006B00037E\r")),
              "error: the bytes are not one whole ASCII frame");
    EXPECT_EQ(whole(Framing::Ascii, chars("x:1103006B00037E\r\n")),
              "error: the bytes are not one whole ASCII frame");
    EXPECT_EQ(whole(Framing::Ascii, chars(":1103006B00037E\r\n:")),
              "error: the bytes are not one whole ASCII frame");
}

TEST(WholeFrame, ALenientFramerStillRefusesABadChecksum) {
    Framer lenient({.framing = Framing::Ascii, .lenient = true});
    EXPECT_EQ(shown(lenient.whole_frame(chars(":1103006B00030E\r\n"))),
              "error: the ASCII frame is broken: LRC mismatch: frame has 0x0E, computed 0x7E");
}

TEST(WholeFrame, ForgetsAPartialFrameAndLeavesTheFramerReadyForAStream) {
    Framer framer({Framing::Ascii});
    std::size_t consumed = 0;
    const auto half = chars(":1103");
    EXPECT_EQ(framer.feed(half, consumed).status, FrameStatus::NeedMore);
    EXPECT_TRUE(framer.has_partial());
    EXPECT_EQ(shown(framer.whole_frame(chars(":1103006B00037E\r\n"))),
              "ASCII unit 0x11 pdu [03 00 6B 00 03]");
    EXPECT_FALSE(framer.has_partial());
    EXPECT_EQ(shown(framer.whole_frame(chars(":1103"))),
              "error: the bytes are not one whole ASCII frame");
    EXPECT_FALSE(framer.has_partial());
    const auto next = chars(":1103006B00037E\r\n");
    const auto event = framer.feed(next, consumed);
    ASSERT_TRUE(event.is_frame());
    EXPECT_EQ(to_hex(event.pdu), "03 00 6B 00 03");
}

TEST(WholeFrame, WrittenFramesComeBackWhole) {
    const auto pdu = hex("10 00 01 00 02 04 00 0A 01 02");
    for (Framing framing : {Framing::Mbap, Framing::Rtu, Framing::Ascii}) {
        SCOPED_TRACE(framing_name(framing));
        std::array<std::uint8_t, limits::kMaxAsciiChars> out{};
        const AduHeader header{framing, 0x2A,
                               static_cast<std::uint16_t>(framing == Framing::Mbap ? 9 : 0)};
        const auto size = write_adu(header, pdu, out);
        Framer framer({framing});
        const auto adu = framer.whole_frame(std::span(out).first(size));
        ASSERT_TRUE(adu) << adu.error();
        EXPECT_EQ(adu->header.unit, 0x2A);
        EXPECT_EQ(adu->header.transaction_id, header.transaction_id);
        EXPECT_EQ(to_hex(adu->pdu), to_hex(pdu));
    }
}

TEST(MbapHeaderFields, ReadWithoutJudgingAndConvertedBothWays) {
    // The tester's reading: a protocol id and a length that disagree are reported, not refused.
    const auto bytes = hex("12 34 00 05 00 09 FF 2B 0E");
    const auto frame = read_mbap_frame(bytes);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->header, (AduHeader{Framing::Mbap, 0xFF, 0x1234, 5, 9}));
    EXPECT_EQ(to_hex(frame->pdu), "2B 0E");
    EXPECT_FALSE(read_mbap_frame(hex("12 34 00 05 00 09")));
    const MbapHeader mbap{0x1234, 5, 9, 0xFF};
    EXPECT_EQ(to_adu_header(mbap), frame->header);
    EXPECT_EQ(to_mbap_header(frame->header), mbap);
}

}  // namespace
}  // namespace mblab::protocol
