#include <gtest/gtest.h>

#include <array>
#include <string>

#include "protocol/adu_writer.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;

const auto kPdu = hex("03 00 6B 00 03");

TEST(WriteMbapAdu, ComputesTheLength) {
    std::array<std::uint8_t, 260> out{};
    const MbapHeader header{0x0001, 0, 0x9999, 0x11};
    const std::size_t size = write_mbap_adu(header, kPdu, out);
    ASSERT_EQ(size, 12U);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "00 01 00 00 00 06 11 03 00 6B 00 03");
}

TEST(WriteMbapAdu, KeepsTheProtocolIdItIsGiven) {
    std::array<std::uint8_t, 16> out{};
    const std::size_t size = write_mbap_adu(MbapHeader{0xABCD, 7, 0, 0xFF}, hex("07"), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "AB CD 00 07 00 02 FF 07");
}

TEST(WriteMbapAdu, PduAlreadyInPlace) {
    std::array<std::uint8_t, 32> out{};
    std::copy(kPdu.begin(), kPdu.end(), out.begin() + 7);
    const std::size_t size =
        write_mbap_adu(MbapHeader{2, 0, 0, 1}, std::span(out).subspan(7, kPdu.size()), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "00 02 00 00 00 06 01 03 00 6B 00 03");
}

TEST(WriteMbapAdu, AnAnswerWrittenInItsRoomGetsItsHeaderAround) {
    std::array<std::uint8_t, 32> out{};
    const auto room = mbap_pdu_room(out);
    EXPECT_EQ(room.size(), 25U);
    std::copy(kPdu.begin(), kPdu.end(), room.begin());
    const std::size_t size = write_mbap_adu(MbapHeader{3, 0, 0, 9}, room.first(kPdu.size()), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "00 03 00 00 00 06 09 03 00 6B 00 03");
}

TEST(WriteMbapAdu, ATransactionIdPutIntoAWrittenFrame) {
    std::array<std::uint8_t, 16> out{};
    const std::size_t size = write_mbap_adu(MbapHeader{1, 0, 0, 0x11}, hex("07"), out);
    put_mbap_transaction_id(std::span(out).first(size), 0xBEEF);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "BE EF 00 00 00 02 11 07");
}

TEST(WriteMbapAdu, NoSpaceWritesNothing) {
    std::array<std::uint8_t, 11> out{};
    EXPECT_EQ(write_mbap_adu(MbapHeader{}, kPdu, out), 0U);
    EXPECT_EQ(to_hex(out), "00 00 00 00 00 00 00 00 00 00 00");
}

TEST(WriteMbapAdu, OversizedPduIsWrittenForTheTester) {
    std::vector<std::uint8_t> pdu(300, 0x10);
    std::vector<std::uint8_t> out(400);
    EXPECT_EQ(write_mbap_adu(MbapHeader{}, pdu, out), 307U);
    EXPECT_EQ(to_hex(std::span(out).first(7)), "00 00 00 00 01 2D 00");
}

TEST(WriteRtuAdu, FramesOfTheSpec) {
    std::array<std::uint8_t, 256> out{};
    std::size_t size = write_rtu_adu(0x01, hex("03 00 00 00 0A"), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "01 03 00 00 00 0A C5 CD");
    size = write_rtu_adu(0x11, kPdu, out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "11 03 00 6B 00 03 76 87");
    size = write_rtu_adu(0x01, hex("83 02"), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "01 83 02 C0 F1");
}

TEST(WriteRtuAdu, PduAlreadyInPlace) {
    std::array<std::uint8_t, 16> out{};
    std::copy(kPdu.begin(), kPdu.end(), out.begin() + 1);
    const std::size_t size = write_rtu_adu(0x11, std::span(out).subspan(1, kPdu.size()), out);
    EXPECT_EQ(to_hex(std::span(out).first(size)), "11 03 00 6B 00 03 76 87");
}

TEST(WriteRtuAdu, NoSpace) {
    std::array<std::uint8_t, 7> out{};
    EXPECT_EQ(write_rtu_adu(0x11, kPdu, out), 0U);
}

std::string as_text(std::span<const std::uint8_t> bytes) {
    return {bytes.begin(), bytes.end()};
}

TEST(WriteAsciiAdu, ExampleOfTheSerialSpec) {
    std::array<std::uint8_t, 513> out{};
    const std::size_t size = write_ascii_adu(0x11, kPdu, out);
    EXPECT_EQ(as_text(std::span(out).first(size)), ":1103006B00037E\r\n");
}

TEST(WriteAsciiAdu, UppercaseDigitsAndChosenEnd) {
    std::array<std::uint8_t, 32> out{};
    const std::size_t size = write_ascii_adu(0xF7, hex("AB 0C"), out, '!');
    EXPECT_EQ(as_text(std::span(out).first(size)), ":F7AB0C52\r!");
}

TEST(WriteAsciiAdu, NoSpace) {
    std::array<std::uint8_t, 16> out{};
    EXPECT_EQ(write_ascii_adu(0x11, kPdu, out), 0U);
    EXPECT_EQ(write_ascii_adu(0x11, {}, std::span(out).first(6)), 0U);
    EXPECT_EQ(write_ascii_adu(0x11, {}, std::span(out).first(7)), 7U);
}

}  // namespace
}  // namespace mblab::protocol
