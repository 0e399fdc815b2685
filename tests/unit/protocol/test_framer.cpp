#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "framer_driver.hpp"
#include "protocol/adu.hpp"
#include "protocol/framer.hpp"
#include "support/hex.hpp"

// The one framer over the three framings: the same header and PDU whichever framing carried
// them, and the tester's lenient mode.
namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;

const auto kReadPdu = hex("03 00 6B 00 03");

struct Cut {
    FrameStatus status = FrameStatus::NeedMore;
    AduHeader header;
    std::string pdu;
    std::string violation;
    std::string error;
    std::size_t consumed = 0;
};

Cut cut(Framer& framer, std::span<const std::uint8_t> bytes) {
    std::size_t consumed = 0;
    const FrameEvent event = framer.feed(bytes, consumed);
    return {event.status, event.header, to_hex(event.pdu), event.violation, event.error, consumed};
}

std::vector<std::uint8_t> written(const AduHeader& header, std::span<const std::uint8_t> pdu) {
    std::array<std::uint8_t, limits::kMaxAsciiChars> out{};
    const std::size_t size = write_adu(header, pdu, out);
    EXPECT_EQ(size, adu_size(header.framing, pdu.size()));
    return {out.begin(), out.begin() + static_cast<long>(size)};
}

TEST(Framer, WrittenAduComesBackWithTheSameHeaderAndPduInEveryFraming) {
    for (Framing framing : {Framing::Mbap, Framing::Rtu, Framing::Ascii}) {
        SCOPED_TRACE(framing_name(framing));
        AduHeader header{framing, 0x11};
        if (framing == Framing::Mbap) header.transaction_id = 0x1234;
        const auto adu = written(header, kReadPdu);
        // The writer computes the length field; the framer reports it as received.
        if (framing == Framing::Mbap) header.length = 6;
        Framer framer({framing});
        const Cut got = cut(framer, adu);
        EXPECT_EQ(got.status, FrameStatus::Frame);
        EXPECT_EQ(got.header, header);
        EXPECT_EQ(got.pdu, "03 00 6B 00 03");
        EXPECT_EQ(got.consumed, adu.size());
        EXPECT_FALSE(framer.has_partial());
    }
}

TEST(Framer, WritesTheFramesOfTheSpecs) {
    // [TCPG] MBAP header then the PDU; [SER 2.5.1.2] CRC low byte first; [SER 2.5.2.2] LRC.
    EXPECT_EQ(to_hex(written({Framing::Mbap, 0x11, 0x0001}, kReadPdu)),
              "00 01 00 00 00 06 11 03 00 6B 00 03");
    EXPECT_EQ(to_hex(written({Framing::Rtu, 0x11}, kReadPdu)), "11 03 00 6B 00 03 76 87");
    const auto ascii = written({Framing::Ascii, 0x11}, kReadPdu);
    EXPECT_EQ(std::string(ascii.begin(), ascii.end()), ":1103006B00037E\r\n");
}

TEST(Framer, SilenceEndsAnRtuFrameWhoseLayoutGivesNoLength) {
    // FC 08 echoes any data: only silence says where the request ends.
    const auto adu = written({Framing::Rtu, 1}, hex("08 00 00 12 34 56"));
    Framer framer({Framing::Rtu});
    EXPECT_EQ(cut(framer, adu).status, FrameStatus::NeedMore);
    EXPECT_TRUE(framer.has_partial());
    const FrameEvent event = framer.on_silence();
    ASSERT_TRUE(event.is_frame());
    EXPECT_EQ(to_hex(event.pdu), "08 00 00 12 34 56");
}

TEST(Framer, SilenceMeansNothingToMbapAndDropsAnUnfinishedAsciiFrame) {
    Framer mbap({Framing::Mbap});
    EXPECT_EQ(cut(mbap, hex("00 01 00 00 00 06 11 03")).status, FrameStatus::NeedMore);
    EXPECT_EQ(mbap.on_silence().status, FrameStatus::NeedMore);
    EXPECT_TRUE(mbap.has_partial()) << "MBAP frames end by their length alone";
    ASSERT_TRUE(mbap.partial_frame().has_value());
    EXPECT_EQ(mbap.partial_frame()->header.transaction_id, 1);
    EXPECT_EQ(to_hex(mbap.partial_frame()->pdu), "03");

    Framer ascii({Framing::Ascii});
    const std::string half = ":1103";
    EXPECT_EQ(cut(ascii, std::span(reinterpret_cast<const std::uint8_t*>(half.data()), half.size()))
                  .status,
              FrameStatus::NeedMore);
    EXPECT_TRUE(ascii.on_silence().is_error());
    EXPECT_FALSE(ascii.has_partial());
}

TEST(Framer, StrictMbapRefusesWhatTheLenientOneHandsOverWithItsViolation) {
    const auto other_protocol = hex("00 07 00 01 00 06 11 03 00 6B 00 03");
    const auto no_function = hex("00 08 00 00 00 01 11");
    Framer strict({Framing::Mbap});
    EXPECT_EQ(cut(strict, other_protocol).status, FrameStatus::Error);
    EXPECT_EQ(cut(strict, no_function).status, FrameStatus::Error);

    Framer lenient({.framing = Framing::Mbap, .lenient = true});
    const Cut protocol = cut(lenient, other_protocol);
    EXPECT_EQ(protocol.status, FrameStatus::Frame);
    EXPECT_EQ(protocol.header.protocol_id, 1);
    EXPECT_EQ(protocol.header.transaction_id, 7);
    EXPECT_EQ(protocol.violation, "MBAP protocol id 0x0001 is not 0 (Modbus)");
    const Cut empty = cut(lenient, no_function);
    EXPECT_EQ(empty.status, FrameStatus::Frame);
    EXPECT_EQ(empty.pdu, "");
    EXPECT_EQ(empty.consumed, 7U);
    EXPECT_EQ(empty.violation, "MBAP length 1 is under 2 (unit id and function code)");
}

TEST(Framer, LengthsThatGiveNoFrameAreErrorsEvenWhenLenient) {
    for (const char* header : {"00 01 00 00 00 00 11", "00 01 00 00 01 00 11"}) {
        SCOPED_TRACE(header);
        Framer lenient({.framing = Framing::Mbap, .lenient = true});
        const Cut got = cut(lenient, hex(header));
        EXPECT_EQ(got.status, FrameStatus::Error);
        EXPECT_EQ(got.consumed, 7U);
    }
}

TEST(Framer, LenientSerialFramingHandsOverABadChecksumWithItsViolation) {
    auto rtu = written({Framing::Rtu, 0x11}, kReadPdu);
    rtu.back() ^= 0xFF;
    Framer strict_rtu({.framing = Framing::Rtu, .direction = Direction::Request});
    EXPECT_EQ(cut(strict_rtu, rtu).status, FrameStatus::Error);
    Framer rtu_framer({.framing = Framing::Rtu, .direction = Direction::Request, .lenient = true});
    const Cut got = cut(rtu_framer, rtu);
    EXPECT_EQ(got.status, FrameStatus::Frame);
    EXPECT_EQ(got.pdu, "03 00 6B 00 03");
    EXPECT_EQ(got.violation, "CRC mismatch: frame has 0x7876, computed 0x8776");

    auto ascii = written({Framing::Ascii, 0x11}, kReadPdu);
    ascii[ascii.size() - 4] = '0';  // the LRC's first digit
    Framer ascii_framer({.framing = Framing::Ascii, .lenient = true});
    const Cut lrc = cut(ascii_framer, ascii);
    EXPECT_EQ(lrc.status, FrameStatus::Frame);
    EXPECT_EQ(lrc.header, (AduHeader{Framing::Ascii, 0x11}));
    EXPECT_EQ(lrc.violation, "LRC mismatch: frame has 0x0E, computed 0x7E");
}

TEST(Framer, AsciiDelimiterIsTheFramersOwn) {
    Framer framer({Framing::Ascii});
    framer.set_ascii_delimiter('!');
    EXPECT_EQ(framer.ascii_delimiter(), '!');
    std::array<std::uint8_t, 32> out{};
    const std::size_t size = write_adu({Framing::Ascii, 0x11}, kReadPdu, out, '!');
    EXPECT_EQ(cut(framer, std::span(out).first(size)).status, FrameStatus::Frame);
    Framer mbap({Framing::Mbap});
    EXPECT_EQ(mbap.ascii_delimiter(), '\n');
}

TEST(Framer, ChunkingDoesNotChangeWhatIsCut) {
    // The framer keeps partial-frame state: any split of the stream gives the same frames.
    const auto stream = test::concat({written({Framing::Mbap, 1, 1}, kReadPdu),
                                      hex("00 02 00 05 00 03 01 03 00"),  // protocol id 5
                                      written({Framing::Mbap, 2, 3}, kReadPdu)});
    const auto events = test::run_all_chunkings(Framer({Framing::Mbap}), stream);
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0].status, FrameStatus::Frame);
    EXPECT_EQ(events[1].status, FrameStatus::Error);
    EXPECT_EQ(events[2].status, FrameStatus::Frame);
    EXPECT_EQ(events[2].unit, 2U);
}

}  // namespace
}  // namespace mblab::protocol
