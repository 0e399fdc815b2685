#include <gtest/gtest.h>

#include "framer_driver.hpp"
#include "protocol/mbap_framer.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using namespace mblab::test;

Seen mbap_frame(std::string_view adu_hex, std::string_view pdu_hex, MbapHeader header) {
    Seen out = test::frame(adu_hex, pdu_hex, header.unit_id);
    out.mbap = header;
    return out;
}

const auto kReadRequest = hex("00 01 00 00 00 06 11 03 00 6B 00 03");

TEST(MbapFramer, OneFrameGivesHeaderAduAndPdu) {
    const auto events = run_all_chunkings(MbapFramer{}, kReadRequest);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], mbap_frame("00 01 00 00 00 06 11 03 00 6B 00 03", "03 00 6B 00 03",
                                    MbapHeader{0x0001, 0, 6, 0x11}));
}

TEST(MbapFramer, SeveralFramesInOneChunkComeOneByOne) {
    const auto stream =
        concat({hex("00 01 00 00 00 06 FF 03 00 00 00 01"), hex("00 02 00 00 00 02 00 07"),
                hex("12 34 00 00 00 05 01 2B 0E 01 00")});
    const auto events = run_all_chunkings(MbapFramer{}, stream);
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0], mbap_frame("00 01 00 00 00 06 FF 03 00 00 00 01", "03 00 00 00 01",
                                    MbapHeader{1, 0, 6, 0xFF}));
    EXPECT_EQ(events[1], mbap_frame("00 02 00 00 00 02 00 07", "07", MbapHeader{2, 0, 2, 0}));
    EXPECT_EQ(events[2], mbap_frame("12 34 00 00 00 05 01 2B 0E 01 00", "2B 0E 01 00",
                                    MbapHeader{0x1234, 0, 5, 1}));
}

TEST(MbapFramer, FeedStopsAfterTheFirstFrame) {
    MbapFramer framer;
    const auto stream = concat({kReadRequest, kReadRequest});
    std::size_t consumed = 0;
    const FrameEvent event = framer.feed(stream, consumed);
    EXPECT_EQ(event.status, FrameStatus::Frame);
    EXPECT_EQ(consumed, kReadRequest.size());
}

TEST(MbapFramer, WholeFrameInInputIsReportedWithoutCopy) {
    MbapFramer framer;
    std::size_t consumed = 0;
    const FrameEvent event = framer.feed(kReadRequest, consumed);
    EXPECT_EQ(event.adu.data(), kReadRequest.data());
}

TEST(MbapFramer, PartialHeaderAndPartialFrameAreVisible) {
    MbapFramer framer;
    std::size_t consumed = 0;
    EXPECT_FALSE(framer.has_partial());
    EXPECT_EQ(framer.feed(std::span(kReadRequest).first(3), consumed).status,
              FrameStatus::NeedMore);
    EXPECT_EQ(consumed, 3U);
    EXPECT_TRUE(framer.has_partial());
    EXPECT_FALSE(framer.partial_frame().has_value());

    EXPECT_EQ(framer.feed(std::span(kReadRequest).subspan(3, 4), consumed).status,
              FrameStatus::NeedMore);
    ASSERT_TRUE(framer.partial_frame().has_value());
    EXPECT_EQ(to_mbap_header(framer.partial_frame()->header), (MbapHeader{1, 0, 6, 0x11}));
    EXPECT_TRUE(framer.partial_frame()->pdu.empty());

    EXPECT_EQ(framer.feed(std::span(kReadRequest).subspan(7, 2), consumed).status,
              FrameStatus::NeedMore);
    ASSERT_TRUE(framer.partial_frame().has_value());
    EXPECT_EQ(test::to_hex(framer.partial_frame()->pdu), "03 00") << "the PDU bytes so far";

    EXPECT_EQ(framer.feed(std::span(kReadRequest).subspan(9), consumed).status, FrameStatus::Frame);
    EXPECT_FALSE(framer.has_partial());
    EXPECT_FALSE(framer.partial_frame().has_value());
}

TEST(MbapFramer, ResetDropsThePartialFrame) {
    MbapFramer framer;
    std::size_t consumed = 0;
    (void)framer.feed(std::span(kReadRequest).first(9), consumed);
    framer.reset();
    EXPECT_FALSE(framer.has_partial());
    const FrameEvent event = framer.feed(kReadRequest, consumed);
    EXPECT_EQ(event.status, FrameStatus::Frame);
    EXPECT_EQ(test::to_hex(event.adu), test::to_hex(kReadRequest));
}

// [TCPG 4.4.2.2] and a length field out of range: the frame is dropped and the next one still
// found.
TEST(MbapFramer, ProtocolIdNotZeroSkipsTheFrameAndKeepsStep) {
    const auto bad = hex("00 07 00 01 00 06 11 03 00 6B 00 03");
    const auto events = run_all_chunkings(MbapFramer{}, concat({bad, kReadRequest}));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0].status, FrameStatus::Error);
    EXPECT_EQ(events[0].error, "MBAP protocol id 0x0001 is not 0 (Modbus); 12-byte frame skipped");
    EXPECT_EQ(events[0].adu, test::to_hex(bad));
    EXPECT_EQ(events[0].mbap, (MbapHeader{7, 1, 6, 0x11}));
    EXPECT_EQ(events[1], mbap_frame("00 01 00 00 00 06 11 03 00 6B 00 03", "03 00 6B 00 03",
                                    MbapHeader{1, 0, 6, 0x11}));
}

struct BadLength {
    const char* header;
    const char* error;
};

class MbapFramerBadLength : public ::testing::TestWithParam<BadLength> {};

// The length cannot be trusted, so the framer resets after the header (the server closes).
TEST_P(MbapFramerBadLength, IsAnErrorAfterTheHeader) {
    const auto header = hex(GetParam().header);
    const auto events = run_all_chunkings(MbapFramer{}, header);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].status, FrameStatus::Error);
    EXPECT_EQ(events[0].error, GetParam().error);
    EXPECT_EQ(events[0].mbap, read_mbap_header(header));

    MbapFramer framer;
    std::size_t consumed = 0;
    (void)framer.feed(concat({header, hex("03 00")}), consumed);
    EXPECT_EQ(consumed, 7U);
    EXPECT_FALSE(framer.has_partial());
}

INSTANTIATE_TEST_SUITE_P(
    Lengths, MbapFramerBadLength,
    ::testing::Values(
        BadLength{"00 01 00 00 00 00 01", "MBAP length 0 is under 2 (unit id and function code)"},
        BadLength{"00 01 00 00 00 01 01", "MBAP length 1 is under 2 (unit id and function code)"},
        BadLength{"00 01 00 00 00 FF 01", "MBAP length 255 exceeds 254 (ADU over 260 bytes)"},
        BadLength{"00 01 00 00 01 2C 01", "MBAP length 300 exceeds 254 (ADU over 260 bytes)"},
        BadLength{"00 01 00 00 FF FF 01", "MBAP length 65535 exceeds 254 (ADU over 260 bytes)"},
        // A bad length wins over a bad protocol id: there is nothing to skip by.
        BadLength{"00 01 00 05 01 00 01", "MBAP length 256 exceeds 254 (ADU over 260 bytes)"}));

TEST(MbapFramer, LargestFrameIs260Bytes) {
    std::vector<std::uint8_t> adu = hex("00 09 00 00 00 FE 01 10");
    adu.resize(260, 0xA5);
    const auto events = run_all_chunkings(MbapFramer{}, concat({adu, kReadRequest}));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0].status, FrameStatus::Frame);
    EXPECT_EQ(events[0].adu, test::to_hex(adu));
    EXPECT_EQ(events[0].pdu, test::to_hex(std::span(adu).subspan(7)));
    EXPECT_EQ(events[1].status, FrameStatus::Frame);
}

TEST(MbapFramer, ShortestFrameIsABareFunctionCode) {
    const auto events = run_all_chunkings(MbapFramer{}, hex("00 03 00 00 00 02 01 11"));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], mbap_frame("00 03 00 00 00 02 01 11", "11", MbapHeader{3, 0, 2, 1}));
}

// Lengths that are within limits but disagree with the bytes sent are the PDU decoder's and the
// server's business (a length longer than the bytes sent): the framer only waits for the declared
// bytes.
TEST(MbapFramer, LengthLongerThanTheBytesSentWaits) {
    MbapFramer framer;
    std::size_t consumed = 0;
    const auto short_frame = hex("00 01 00 00 00 08 11 03 00 6B 00 03");
    EXPECT_EQ(framer.feed(short_frame, consumed).status, FrameStatus::NeedMore);
    EXPECT_EQ(consumed, short_frame.size());
    EXPECT_TRUE(framer.has_partial());
}

TEST(MbapFramer, EmptyInputNeedsMore) {
    MbapFramer framer;
    std::size_t consumed = 99;
    EXPECT_EQ(framer.feed({}, consumed).status, FrameStatus::NeedMore);
    EXPECT_EQ(consumed, 0U);
}

}  // namespace
}  // namespace mblab::protocol

namespace mblab::protocol {
namespace {

using mblab::test::hex;

// Issue 17 item 8: what follows a header of length 0xFF is that frame's body unless whole frames
// read from some point to the end.
TEST(MbapResync, BodyAloneHasNoFrames) {
    const auto body = hex("01 03 00 00 00 01");
    EXPECT_EQ(mbap_resync_offset(body), body.size());
}

TEST(MbapResync, FindsARequestThatFollowsTheBody) {
    EXPECT_EQ(mbap_resync_offset(hex("03 00 00 00 01  00 02 00 00 00 06 01 03 00 00 00 01")), 5U);
}

TEST(MbapResync, FindsFramesFollowedByTheStartOfAnother) {
    EXPECT_EQ(mbap_resync_offset(hex("03 00  00 02 00 00 00 03 01 08 00  00 03 00 00 00")), 2U);
    EXPECT_EQ(mbap_resync_offset(hex("03 00  00 02 00 00 00 03 01 08 00  00 03 00 01 00")), 16U);
}

TEST(MbapResync, IgnoresRunsThatDoNotReachTheEnd) {
    const auto bytes = hex("03  00 02 00 00 00 03 01 08 00  FF FF FF FF FF FF FF FF");
    EXPECT_EQ(mbap_resync_offset(bytes), bytes.size());
}

}  // namespace
}  // namespace mblab::protocol
