#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>

#include "client/frame_reader.hpp"
#include "support/hex.hpp"

// The client links' receiving half as hex in, Received out: no socket, no clock.
namespace mblab::client {
namespace {

using test::hex;
using test::to_hex;

// What the reader handed over, which must be there and of `status` (a Timeout when missing, so the
// checks that follow fail too).
Received handed_over(std::optional<Received> got, ReceiveStatus status) {
    EXPECT_TRUE(got.has_value());
    if (!got) return {};
    EXPECT_EQ(got->status, status);
    return std::move(*got);
}

FrameReader tcp_reader() {
    return FrameReader({.framing = Framing::Mbap, .lenient = true});
}

TEST(FrameReader, AnswersThatCameTogetherAreHandedOverOneByOne) {
    FrameReader reader = tcp_reader();
    reader.add(hex("00 01 00 00 00 05 01 03 02 00 2A  00 02 00 00 00 03 01 83 02"));
    const Received first = handed_over(reader.next(), ReceiveStatus::Frame);
    EXPECT_EQ(to_hex(first.bytes), "00 01 00 00 00 05 01 03 02 00 2A");
    EXPECT_EQ(first.header.transaction_id, 1);
    EXPECT_EQ(to_hex(first.pdu), "03 02 00 2A");
    auto second = reader.next();
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->header.transaction_id, 2);
    EXPECT_EQ(to_hex(second->pdu), "83 02");
    EXPECT_FALSE(reader.next().has_value());
    EXPECT_TRUE(reader.empty());
}

TEST(FrameReader, AFrameInPiecesWaitsForItsLastByte) {
    FrameReader reader = tcp_reader();
    reader.add(hex("00 01 00 00 00 05 01"));
    EXPECT_FALSE(reader.next().has_value());
    reader.add(hex("03 02 00"));
    EXPECT_FALSE(reader.next().has_value());
    EXPECT_TRUE(reader.has_partial());
    reader.add(hex("2A"));
    auto frame = reader.next();
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(to_hex(frame->bytes), "00 01 00 00 00 05 01 03 02 00 2A");
}

TEST(FrameReader, ATimeoutHandsOverThePartOfAFrameThatCame) {
    FrameReader reader = tcp_reader();
    reader.add(hex("00 01 00 00 00 05 01 03"));
    EXPECT_FALSE(reader.next().has_value());
    const Received got = reader.take(ReceiveStatus::Timeout);
    EXPECT_EQ(got.status, ReceiveStatus::Timeout);
    EXPECT_EQ(to_hex(got.bytes), "00 01 00 00 00 05 01 03");
    EXPECT_TRUE(reader.empty());
    EXPECT_FALSE(reader.has_partial());
}

TEST(FrameReader, ALengthThatDescribesNoFrameHandsOverEverythingAfterIt) {
    // Nothing after such a header can be trusted to start a frame.
    FrameReader reader = tcp_reader();
    reader.add(hex("00 01 00 00 FF FF 01 03 02 00 2A 00 02 00 00 00 03 01 83 02"));
    const Received got = handed_over(reader.next(), ReceiveStatus::Malformed);
    EXPECT_EQ(to_hex(got.bytes), "00 01 00 00 FF FF 01 03 02 00 2A 00 02 00 00 00 03 01 83 02");
    EXPECT_EQ(got.detail, "MBAP length 65535 exceeds 254 (ADU over 260 bytes)");
    EXPECT_FALSE(reader.next().has_value());
}

TEST(FrameReader, ATcpLinkHandsOverAForeignProtocolIdForTheTesterToJudge) {
    FrameReader reader = tcp_reader();
    reader.add(hex("00 01 00 07 00 05 01 03 02 00 2A"));
    const Received got = handed_over(reader.next(), ReceiveStatus::Frame);
    EXPECT_EQ(got.header.protocol_id, 7);
    EXPECT_EQ(got.violation, "MBAP protocol id 0x0007 is not 0 (Modbus)");
}

TEST(FrameReader, ABadCrcOnALineIsMalformedAndTheNextFrameIsKept) {
    FrameReader reader({.framing = Framing::Rtu, .direction = protocol::Direction::Response});
    reader.add(hex("01 03 02 00 2A 00 00  01 03 02 00 2A 39 9B"));
    const Received bad = handed_over(reader.next(), ReceiveStatus::Malformed);
    EXPECT_EQ(to_hex(bad.bytes), "01 03 02 00 2A 00 00");
    EXPECT_EQ(bad.detail, "CRC mismatch: frame has 0x0000, computed 0x9B39");
    const Received good = handed_over(reader.next(), ReceiveStatus::Frame);
    EXPECT_EQ(good.header, (protocol::AduHeader{Framing::Rtu, 1}));
    EXPECT_EQ(to_hex(good.pdu), "03 02 00 2A");
}

TEST(FrameReader, SilenceEndsAnAnswerWhoseLayoutGivesNoLength) {
    // An FC 08 echo: its length is only known when the line goes quiet.
    FrameReader reader({.framing = Framing::Rtu, .direction = protocol::Direction::Response});
    reader.add(hex("01 08 00 00 12 34 ED 7C"));
    EXPECT_FALSE(reader.next().has_value());
    const Received got = handed_over(reader.on_silence(), ReceiveStatus::Frame);
    EXPECT_EQ(to_hex(got.pdu), "08 00 00 12 34");
}

}  // namespace
}  // namespace mblab::client
