#include <gtest/gtest.h>

#include "framer_driver.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/rtu_framer.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using namespace mblab::test;
using Segments = std::vector<std::vector<std::uint8_t>>;

const RtuFramer kRequests{Direction::Request};
const RtuFramer kResponses{Direction::Response};

// An RTU ADU around a PDU given in hex (the CRC itself is checked against vectors in
// test_crc16.cpp and in the literal frames below).
std::vector<std::uint8_t> rtu(std::uint8_t address, std::string_view pdu_hex) {
    const auto pdu = hex(pdu_hex);
    std::vector<std::uint8_t> out(pdu.size() + 3);
    out.resize(write_rtu_adu(address, pdu, out));
    return out;
}

Seen frame_of(const std::vector<std::uint8_t>& adu) {
    return test::frame(to_hex(adu), to_hex(std::span(adu).subspan(1, adu.size() - 3)), adu[0]);
}

Seen error(std::string text, const std::vector<std::uint8_t>& adu = {}) {
    Seen out;
    out.status = FrameStatus::Error;
    out.error = std::move(text);
    out.adu = to_hex(adu);
    if (!adu.empty()) out.unit = adu[0];
    return out;
}

// Feeds the frames back to back (or with silence between them) and expects each one back.
void expect_each_frame(const RtuFramer& prototype, const Segments& frames, bool with_silence) {
    std::vector<std::uint8_t> stream;
    for (const auto& adu : frames)
        stream.insert(stream.end(), adu.begin(), adu.end());
    const auto events = with_silence ? run_all_chunkings(prototype, frames, true)
                                     : run_all_chunkings(prototype, stream);
    ASSERT_EQ(events.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i)
        EXPECT_EQ(events[i], frame_of(frames[i]));
}

TEST(RtuFramer, FrameOfTheSpecWithItsCrc) {
    const auto events = run_all_chunkings(kRequests, hex("01 03 00 00 00 0A C5 CD"));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], test::frame("01 03 00 00 00 0A C5 CD", "03 00 00 00 0A", 1));
}

// Every layout of the request table, back to back without silence: each end is found from the
// function code alone.
TEST(RtuFramer, EveryRequestLayoutEndsWithoutSilence) {
    const Segments frames = {
        rtu(1, "01 00 13 00 25"),
        rtu(1, "02 00 C4 00 16"),
        rtu(1, "03 00 6B 00 03"),
        rtu(1, "04 00 08 00 01"),
        rtu(1, "05 00 AC FF 00"),
        rtu(1, "06 00 01 00 03"),
        rtu(1, "07"),
        rtu(1, "08 00 0A 00 00"),  // clear counters: one data word
        rtu(1, "0B"),
        rtu(1, "0C"),
        rtu(1, "0F 00 13 00 0A 02 CD 01"),
        rtu(1, "10 00 01 00 02 04 00 0A 01 02"),
        rtu(1, "11"),
        rtu(1, "14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02"),
        rtu(1, "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"),
        rtu(1, "16 00 04 00 F2 00 25"),
        rtu(1, "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF"),
        rtu(1, "18 04 DE"),
        rtu(1, "2B 0E 01 00"),
        rtu(1, "5B 09 00 00 01 00 01 00 07 00 01"),
    };
    expect_each_frame(kRequests, frames, false);
}

TEST(RtuFramer, EveryResponseLayoutEndsWithoutSilence) {
    const Segments frames = {
        rtu(1, "01 03 CD 6B 05"),
        rtu(1, "02 03 AC DB 35"),
        rtu(1, "03 06 02 2B 00 00 00 64"),
        rtu(1, "04 02 00 0A"),
        rtu(1, "05 00 AC FF 00"),
        rtu(1, "06 00 01 00 03"),
        rtu(1, "07 6D"),
        rtu(1, "08 00 0B 00 05"),
        rtu(1, "0B 00 00 01 08"),
        rtu(1, "0C 08 00 00 01 08 01 21 20 00"),
        rtu(1, "0F 00 13 00 0A"),
        rtu(1, "10 00 01 00 02"),
        rtu(1, "11 03 01 FF 42"),
        rtu(1, "14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40"),
        rtu(1, "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"),
        rtu(1, "16 00 04 00 F2 00 25"),
        rtu(1, "17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF"),
        rtu(1, "18 00 06 00 02 01 B8 12 84"),
        rtu(1, "2B 0E 01 01 00 00 03 00 03 41 42 43 01 02 58 59 02 00"),
        rtu(1, "5B 0B 00 00 01 00 01 00 08 00 00 00 2A"),
        rtu(1, "83 02"),
        rtu(1, "AB 01"),
    };
    expect_each_frame(kResponses, frames, false);
}

TEST(RtuFramer, ExceptionResponseOfTheSpec) {
    const auto events = run_all_chunkings(kResponses, hex("01 83 02 C0 F1"));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], test::frame("01 83 02 C0 F1", "83 02", 1));
}

TEST(RtuFramer, WholeFrameInInputIsReportedWithoutCopy) {
    RtuFramer framer{Direction::Request};
    const auto adu = hex("01 03 00 00 00 0A C5 CD");
    std::size_t consumed = 0;
    EXPECT_EQ(framer.feed(adu, consumed).adu.data(), adu.data());
}

// FC 08 sub-function 00 echoes any number of bytes: only silence ends it.
TEST(RtuFramer, EchoOfDiagnosticsEndsAtSilence) {
    const auto echo = hex("01 08 00 00 12 34 ED 7C");
    RtuFramer framer{Direction::Request};
    std::size_t consumed = 0;
    EXPECT_EQ(framer.feed(echo, consumed).status, FrameStatus::NeedMore);
    EXPECT_TRUE(framer.has_partial());

    const auto events = run_all_chunkings(kRequests, Segments{echo}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], test::frame("01 08 00 00 12 34 ED 7C", "08 00 00 12 34", 1));
}

TEST(RtuFramer, UnknownFunctionCodeEndsAtSilence) {
    const auto adu = rtu(0x11, "41 01 02 03 04 05 06 07 08 09");
    const auto events = run_all_chunkings(kRequests, Segments{adu, rtu(0x11, "07")}, true);
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], frame_of(adu));
    EXPECT_EQ(events[1], frame_of(rtu(0x11, "07")));
}

TEST(RtuFramer, UnknownDiagnosticSubFunctionAndForeignMeiEndAtSilence) {
    const Segments frames = {rtu(1, "08 00 63 00 00 00 00"), rtu(1, "2B 0D 00 01 02 03"),
                             rtu(1, "07")};
    expect_each_frame(kRequests, frames, true);
}

// For links without silence (RTU over TCP) the CRC can end frames of unknown length.
TEST(RtuFramer, EndOnCrcMatchEndsTheEchoWithoutSilence) {
    const RtuFramer framer{Direction::Request, RtuFramer::UnknownLength::EndOnCrcMatch};
    const auto echo = rtu(1, "08 00 00 A5 5A 01 02");
    const auto other = rtu(1, "41 FF");
    const auto events =
        run_all_chunkings(framer, concat({echo, other, hex("01 03 00 00 00 0A C5 CD")}));
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0], frame_of(echo));
    EXPECT_EQ(events[1], frame_of(other));
    EXPECT_EQ(events[2], test::frame("01 03 00 00 00 0A C5 CD", "03 00 00 00 0A", 1));
}

TEST(RtuFramer, BadCrcIsDroppedAndTheNextFrameIsKept) {
    const auto bad = hex("01 03 00 00 00 0A C5 CE");
    const auto good = hex("11 03 00 6B 00 03 76 87");
    const auto events = run_all_chunkings(kRequests, concat({bad, good}));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("CRC mismatch: frame has 0xCEC5, computed 0xCDC5", bad));
    EXPECT_EQ(events[1], test::frame("11 03 00 6B 00 03 76 87", "03 00 6B 00 03", 0x11));
}

// A response whose byte count was corrupted to `count`, then silence, then a good response.
std::vector<Seen> corrupted_count_then_good(std::string_view pdu_hex, std::uint8_t count) {
    auto bad = rtu(1, pdu_hex);
    bad[2] = count;
    return run_all_chunkings(kResponses, Segments{bad, rtu(1, "03 02 00 0A")});
}

// A byte count corrupted upwards makes the layout promise more bytes than come; silence ends
// the wait and the frame after it is not lost.
TEST(RtuFramer, CountCorruptedUpwardsResyncsAtSilence) {
    const auto events = corrupted_count_then_good("03 04 00 01 00 02", 0x40);
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0].status, FrameStatus::Error);
    EXPECT_EQ(events[0].error, "incomplete frame: silence after 9 bytes, layout needs 69");
    EXPECT_EQ(events[1], frame_of(rtu(1, "03 02 00 0A")));
}

// A byte count corrupted downwards cuts the frame short: a CRC error, then the tail is taken as
// frames until silence drops what is held; the frame after the silence is kept.
TEST(RtuFramer, CountCorruptedDownwardsResyncsAtSilence) {
    const auto events = corrupted_count_then_good("03 08 00 01 00 02 00 03 00 04", 0x02);
    ASSERT_GE(events.size(), 2U);
    EXPECT_EQ(events[0].error, "CRC mismatch: frame has 0x0200, computed 0x8479");
    for (std::size_t i = 0; i + 1 < events.size(); ++i) {
        EXPECT_EQ(events[i].status, FrameStatus::Error) << "event " << i;
    }
    EXPECT_EQ(events.back(), frame_of(rtu(1, "03 02 00 0A")));
}

TEST(RtuFramer, GarbageBetweenFramesIsDroppedAtSilence) {
    const auto good = rtu(1, "03 00 00 00 01");
    const auto events = run_all_chunkings(kRequests, Segments{good, hex("FF 00"), good});
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0], frame_of(good));
    EXPECT_EQ(events[1], error("frame under 4 bytes (2 before silence)"));
    EXPECT_EQ(events[2], frame_of(good));
}

TEST(RtuFramer, FrameUnderFourBytesAtSilence) {
    const auto events = run_all_chunkings(kRequests, Segments{hex("01 07 41")}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], error("frame under 4 bytes (3 before silence)"));
}

// Silence is what delimits RTU frames: a truncated frame with a correct CRC is a frame, and the
// PDU decoder rejects its content (an unknown function code).
TEST(RtuFramer, TruncatedFrameWithCorrectCrcIsAFrameAtSilence) {
    const auto truncated = rtu(1, "03 00 00");
    const auto events = run_all_chunkings(kRequests, Segments{truncated}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], frame_of(truncated));
}

TEST(RtuFramer, IncompleteFrameAtSilenceIsAnError) {
    const auto events = run_all_chunkings(kRequests, Segments{hex("01 03 00 00 00")}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], error("incomplete frame: silence after 5 bytes, layout needs 8",
                               hex("01 03 00 00 00")));
}

TEST(RtuFramer, SilenceWithNothingHeldReportsNothing) {
    RtuFramer framer{Direction::Response};
    EXPECT_EQ(framer.on_silence().status, FrameStatus::NeedMore);
}

TEST(RtuFramer, FrameOf256BytesIsTheLargest) {
    std::vector<std::uint8_t> pdu(253, 0x5A);
    pdu[0] = 0x41;
    std::vector<std::uint8_t> adu(256);
    ASSERT_EQ(write_rtu_adu(9, pdu, adu), 256U);
    const auto events = run_all_chunkings(kRequests, Segments{adu}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], frame_of(adu));
}

TEST(RtuFramer, MoreThan256BytesWithoutAnEndIsAnError) {
    std::vector<std::uint8_t> bytes(257, 0x5A);
    bytes[1] = 0x41;
    const auto events = run_all_chunkings(kRequests, Segments{bytes, rtu(1, "07")});
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0], error("no frame end within 256 bytes"));
    EXPECT_EQ(events[1], frame_of(rtu(1, "07")));
}

TEST(RtuFramer, LayoutAnnouncingMoreThan256BytesEndsAtSilence) {
    // FC 10 for 124 registers: the byte count says 248 bytes, 246 fit in the 256-byte frame.
    std::vector<std::uint8_t> pdu = hex("10 01 00 00 7C F8");
    pdu.resize(252, 0x5A);
    std::vector<std::uint8_t> adu(256);
    adu.resize(write_rtu_adu(1, pdu, adu));
    ASSERT_EQ(adu.size(), 255U);
    const auto events = run_all_chunkings(kRequests, Segments{adu}, true);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], frame_of(adu));

    const auto cut = run_all_chunkings(kResponses, Segments{hex("01 03 FC 00 00")}, true);
    ASSERT_EQ(cut.size(), 1U);
    EXPECT_EQ(cut[0], error("incomplete frame: silence after 5 bytes, layout needs 257",
                            hex("01 03 FC 00 00")));
}

TEST(RtuFramer, LayoutAnnouncingMoreThan256BytesEndsOnCrcMatchWithoutSilence) {
    std::vector<std::uint8_t> pdu = hex("17 00 70 00 01 01 00 00 7A F4");
    pdu.resize(252, 0xA5);
    std::vector<std::uint8_t> adu(256);
    adu.resize(write_rtu_adu(1, pdu, adu));
    RtuFramer framer{Direction::Request, RtuFramer::UnknownLength::EndOnCrcMatch};
    std::size_t consumed = 0;
    const FrameEvent event = framer.feed(adu, consumed);
    EXPECT_EQ(event.status, FrameStatus::Frame);
    EXPECT_EQ(consumed, adu.size());
}

TEST(RtuFramer, DirectionChoosesTheLayout) {
    // As a request, FC 03 is 8 bytes; as a response, its byte count says 7.
    const auto response = hex("01 03 02 00 0A 38 43");
    const auto as_response = run_all_chunkings(kResponses, Segments{response});
    ASSERT_EQ(as_response.size(), 1U);
    EXPECT_EQ(as_response[0], test::frame("01 03 02 00 0A 38 43", "03 02 00 0A", 1));
    RtuFramer framer{Direction::Request};
    std::size_t consumed = 0;
    EXPECT_EQ(framer.feed(response, consumed).status, FrameStatus::NeedMore);
}

TEST(RtuFramer, ResetDropsThePartialFrame) {
    RtuFramer framer{Direction::Request};
    std::size_t consumed = 0;
    (void)framer.feed(hex("01 03 00"), consumed);
    EXPECT_TRUE(framer.has_partial());
    framer.reset();
    EXPECT_FALSE(framer.has_partial());
    EXPECT_EQ(framer.feed(hex("01 03 00 00 00 0A C5 CD"), consumed).status, FrameStatus::Frame);
}

TEST(RtuFramer, BroadcastAddressIsPassedOn) {
    const auto adu = rtu(0, "06 00 01 00 03");
    const auto events = run_all_chunkings(kRequests, Segments{adu});
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], frame_of(adu));
}

}  // namespace
}  // namespace mblab::protocol
