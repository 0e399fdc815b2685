#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "protocol/crc16.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/line_cases.hpp"

namespace mblab::robustness {
namespace {

using protocol::Framing;
using Bytes = std::vector<std::uint8_t>;

std::string text_of(const Bytes& bytes) {
    return {bytes.begin(), bytes.end()};
}

const FuzzCase& named(const std::vector<FuzzCase>& cases, std::string_view name) {
    const auto found =
        std::find_if(cases.begin(), cases.end(), [&](const FuzzCase& c) { return c.name == name; });
    EXPECT_NE(found, cases.end()) << name;
    return *found;
}

TEST(LineFrame, RtuIsAddressPduAndCrcLowByteFirst) {
    EXPECT_EQ(line_frame(Framing::Rtu, 0x11, Bytes{0x03, 0x00, 0x6B, 0x00, 0x03}),
              (Bytes{0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87}));
}

TEST(LineFrame, AsciiIsColonHexLrcCrLf) {
    EXPECT_EQ(text_of(line_frame(Framing::Ascii, 0x01, Bytes{0x03, 0x00, 0x00, 0x00, 0x01})),
              ":010300000001FB\r\n");
}

TEST(OnLine, AnMbapCaseIsReframedWithItsUnitAsTheAddress) {
    FuzzCase c{BadInput::Quantity, "quantity 0", {}, false};
    c.steps.push_back({0, mbap_frame(5, 0x11, Bytes{0x03, 0x00, 0x6B, 0x00, 0x03}), {}});
    const auto rtu = on_line(c, Framing::Rtu);
    ASSERT_TRUE(rtu);
    EXPECT_EQ(rtu->name, "quantity 0");
    ASSERT_EQ(rtu->steps.size(), 1U);
    EXPECT_EQ(rtu->steps[0].bytes, (Bytes{0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87}));
    const auto ascii = on_line(c, Framing::Ascii);
    ASSERT_TRUE(ascii);
    EXPECT_EQ(text_of(ascii->steps[0].bytes), ":1103006B00037E\r\n");
}

TEST(OnLine, AnOversizePduGoesOutWholeWithAGoodCrc) {
    FuzzCase c{BadInput::Oversize, "PDU of 300 bytes", {}, false};
    c.steps.push_back({0, mbap_frame(1, 1, Bytes(300, 0x10)), {}});
    const auto rtu = on_line(c, Framing::Rtu);
    ASSERT_TRUE(rtu);
    EXPECT_EQ(rtu->steps[0].bytes.size(), 303U);
    EXPECT_EQ(protocol::crc16(rtu->steps[0].bytes), 0);
}

TEST(OnLine, WhatTestsMbapOrTcpIsNotReframed) {
    FuzzCase protocol_id{BadInput::ProtocolId, "protocol id 1", {}, false};
    protocol_id.steps.push_back({0, mbap_frame(1, 1, Bytes{0x03, 0, 0, 0, 1}, 1), {}});
    EXPECT_FALSE(on_line(protocol_id, Framing::Rtu));
    FuzzCase wrong_length{BadInput::Mutation, "length 3", {}, false};
    wrong_length.steps.push_back({0, mbap_frame(1, 1, Bytes{0x03, 0, 0, 0, 1}, 0, 3), {}});
    EXPECT_FALSE(on_line(wrong_length, Framing::Rtu));
    FuzzCase second_connection{BadInput::UnitId, "two connections", {}, false};
    second_connection.steps.push_back({1, mbap_frame(1, 1, Bytes{0x03, 0, 0, 0, 1}), {}});
    EXPECT_FALSE(on_line(second_connection, Framing::Ascii));
}

TEST(NotApplicable, EachClassWhereItsFramingIsNot) {
    EXPECT_TRUE(not_applicable(BadInput::ProtocolId, Framing::Rtu));
    EXPECT_TRUE(not_applicable(BadInput::ManyConnections, Framing::Ascii));
    EXPECT_TRUE(not_applicable(BadInput::FrameCheck, Framing::Mbap));
    EXPECT_TRUE(not_applicable(BadInput::LineGap, Framing::Ascii));
    EXPECT_TRUE(not_applicable(BadInput::AsciiText, Framing::Rtu));
    EXPECT_FALSE(not_applicable(BadInput::Quantity, Framing::Rtu));
    EXPECT_FALSE(not_applicable(BadInput::Quantity, Framing::Mbap));
    EXPECT_FALSE(not_applicable(BadInput::LineGap, Framing::Rtu));
}

TEST(LineCases, RtuFrameFaults) {
    const auto cases = line_cases(Framing::Rtu, 0x01, 0, std::chrono::milliseconds(3));
    const Bytes good = {0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A};
    EXPECT_EQ(named(cases, "CRC low byte flipped").steps[0].bytes,
              (Bytes{0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x7B, 0x0A}));
    EXPECT_EQ(named(cases, "CRC bytes swapped").steps[0].bytes,
              (Bytes{0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x0A, 0x84}));
    for (const auto& c : cases) {
        if (c.kind == BadInput::FrameCheck) {
            EXPECT_NE(protocol::crc16(c.steps[0].bytes), 0) << c.name;
        }
        if (c.kind == BadInput::ShortFrame) {
            EXPECT_LT(c.steps[0].bytes.size(), 4U) << c.name;
        }
    }
    EXPECT_EQ(named(cases, "2-byte frame").steps[0].bytes, (Bytes{0x01, 0x03}));
    EXPECT_EQ(named(cases, "address and CRC alone (3 bytes)").steps[0].bytes,
              (Bytes{0x01, 0x7E, 0x80}));
    const auto& gap = named(cases, "good read with a 3 ms gap after byte 4");
    ASSERT_EQ(gap.steps.size(), 2U);
    EXPECT_EQ(gap.steps[0].bytes, (Bytes{0x01, 0x03, 0x00, 0x00}));
    EXPECT_EQ(gap.steps[0].pause, std::chrono::milliseconds(3));
    EXPECT_EQ(gap.steps[1].bytes, (Bytes{0x00, 0x01, 0x84, 0x0A}));
    const auto& noise = named(cases, "4 zero bytes, then a good frame");
    ASSERT_EQ(noise.steps.size(), 2U);
    EXPECT_EQ(noise.steps[0].bytes, Bytes(4, 0x00));
    EXPECT_GE(noise.steps[0].pause, std::chrono::milliseconds(12));
    EXPECT_EQ(noise.steps[1].bytes, good);
}

TEST(LineCases, AsciiTextFaults) {
    const auto cases = line_cases(Framing::Ascii, 0x01, 0, std::chrono::milliseconds(2));
    const std::string good = ":010300000001FB\r\n";
    EXPECT_EQ(text_of(named(cases, "LRC off by one").steps[0].bytes), ":010300000001FC\r\n");
    EXPECT_EQ(text_of(named(cases, "LRC 00").steps[0].bytes), ":01030000000100\r\n");
    EXPECT_EQ(text_of(named(cases, "address and LRC alone").steps[0].bytes), ":01FF\r\n");
    const auto& odd = named(cases, "odd number of hex digits");
    EXPECT_EQ(text_of(odd.steps[0].bytes), ":01300000001FB\r\n");
    EXPECT_EQ(text_of(odd.steps[1].bytes), good);
    EXPECT_EQ(text_of(named(cases, "a character that is not hex").steps[0].bytes),
              ":01G300000001FB\r\n");
    EXPECT_EQ(text_of(named(cases, "no CR LF, then a good frame").steps[0].bytes),
              ":010300000001FB");
    EXPECT_EQ(text_of(named(cases, "CR without LF").steps[0].bytes), ":010300000001FB\r");
    EXPECT_EQ(std::count_if(cases.begin(), cases.end(),
                            [](const FuzzCase& c) { return c.kind == BadInput::LineGap; }),
              0);
}

TEST(LineCases, EveryReframedCaseOnRtuCarriesAGoodCrcToItsAddress) {
    Recon recon;
    recon.served = {0x01, 0x03, 0x06, 0x08, 0x10, 0x2B};
    CaseGenerator generator(recon, {true, std::nullopt}, 3, Framing::Rtu);
    for (std::size_t i = 0; i < generator.fixed_cases() + 200; ++i) {
        const auto c = generator.next();
        EXPECT_FALSE(not_applicable(c.kind, Framing::Rtu)) << c.name;
        if (c.kind == BadInput::FrameCheck || c.kind == BadInput::ShortFrame ||
            c.kind == BadInput::LineGap || c.kind == BadInput::Noise)
            continue;
        for (const auto& step : c.steps)
            EXPECT_EQ(protocol::crc16(step.bytes), 0) << c.name;
    }
}

}  // namespace
}  // namespace mblab::robustness
