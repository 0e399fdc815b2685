// The function table against the codec: each row's layouts must measure frames the codec accepts,
// and a code decodes to a typed message exactly when it has a row.
#include <gtest/gtest.h>

#include <string>
#include <variant>
#include <vector>

#include "protocol/function_table.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"
#include "protocol/rtu_frame_length.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using Kind = RtuFrameLength::Kind;

// One well-formed request and response PDU per row, mostly the examples of [APP] section 6.
struct Sample {
    FunctionCode code;
    const char* request;
    const char* response;
};

constexpr Sample kSamples[] = {
    {FunctionCode::ReadCoils, "01 00 13 00 13", "01 03 CD 6B 05"},
    {FunctionCode::ReadDiscreteInputs, "02 00 C4 00 16", "02 03 AC DB 35"},
    {FunctionCode::ReadHoldingRegisters, "03 00 6B 00 03", "03 06 02 2B 00 00 00 64"},
    {FunctionCode::ReadInputRegisters, "04 00 08 00 01", "04 02 00 0A"},
    {FunctionCode::WriteSingleCoil, "05 00 AC FF 00", "05 00 AC FF 00"},
    {FunctionCode::WriteSingleRegister, "06 00 01 00 03", "06 00 01 00 03"},
    {FunctionCode::ReadExceptionStatus, "07", "07 6D"},
    {FunctionCode::Diagnostics, "08 00 0B 00 00", "08 00 0B 00 05"},
    {FunctionCode::GetCommEventCounter, "0B", "0B FF FF 01 08"},
    {FunctionCode::GetCommEventLog, "0C", "0C 08 00 00 01 08 01 21 20 00"},
    {FunctionCode::WriteMultipleCoils, "0F 00 13 00 0A 02 CD 01", "0F 00 13 00 0A"},
    {FunctionCode::WriteMultipleRegisters, "10 00 01 00 02 04 00 0A 01 02", "10 00 01 00 02"},
    {FunctionCode::ReportServerId, "11", "11 03 2A FF 01"},
    {FunctionCode::ReadFileRecord, "14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02",
     "14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40"},
    {FunctionCode::WriteFileRecord, "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
     "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"},
    {FunctionCode::MaskWriteRegister, "16 00 04 00 F2 00 25", "16 00 04 00 F2 00 25"},
    {FunctionCode::ReadWriteMultipleRegisters, "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF",
     "17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF"},
    {FunctionCode::ReadFifoQueue, "18 04 DE", "18 00 06 00 02 01 B8 12 84"},
    {FunctionCode::EncapsulatedInterface, "2B 0E 01 00",
     "2B 0E 01 01 00 00 02 00 03 41 42 43 01 02 76 31"},
    {FunctionCode::ObjectMessaging, "5B 09 00 00 01 00 01 00 07 00 01",
     "5B 0B 00 00 01 00 01 00 08 00 00 00 2A"},
};

// The RTU frame around a PDU: address 01 in front, a CRC behind (its value does not matter here).
std::vector<std::uint8_t> rtu_frame(const std::vector<std::uint8_t>& pdu) {
    std::vector<std::uint8_t> frame{0x01};
    frame.insert(frame.end(), pdu.begin(), pdu.end());
    frame.insert(frame.end(), {0x00, 0x00});
    return frame;
}

// Feeds the frame a byte at a time, as a serial receiver would: every answer before the end asks
// for more within the frame, and the frame's own size is what it finally names.
void expect_measured(Direction direction, const std::vector<std::uint8_t>& pdu) {
    const auto frame = rtu_frame(pdu);
    std::size_t held = 0;
    for (;;) {
        const RtuFrameLength length =
            rtu_frame_length(direction, std::span(frame).first(std::min(held, frame.size())));
        ASSERT_NE(length.kind, Kind::Unknown) << "after " << held << " bytes";
        if (length.kind == Kind::Known) {
            EXPECT_EQ(length.bytes, frame.size());
            EXPECT_LE(held, frame.size());
            return;
        }
        ASSERT_GT(length.bytes, held);
        ASSERT_LE(length.bytes, frame.size());
        held = length.bytes;
    }
}

TEST(FunctionTable, EveryRowHasASample) {
    ASSERT_EQ(std::size(kSamples), std::size(kFunctionTable));
    for (std::size_t i = 0; i < std::size(kSamples); ++i)
        EXPECT_EQ(kSamples[i].code, kFunctionTable[i].code) << "row " << i;
}

TEST(FunctionTable, SamplesAreWhatTheCodecAccepts) {
    for (const Sample& sample : kSamples) {
        const auto request = decode_request(hex(sample.request));
        ASSERT_TRUE(request) << sample.request;
        EXPECT_EQ(function_of(request.value()), static_cast<std::uint8_t>(sample.code));
        const auto response = decode_response(hex(sample.response));
        ASSERT_TRUE(response) << sample.response;
        EXPECT_EQ(function_of(response.value()), static_cast<std::uint8_t>(sample.code));
    }
}

TEST(FunctionTable, LayoutsMeasureTheSamples) {
    for (const Sample& sample : kSamples) {
        SCOPED_TRACE(std::string(function_name(static_cast<std::uint8_t>(sample.code))));
        expect_measured(Direction::Request, hex(sample.request));
        expect_measured(Direction::Response, hex(sample.response));
    }
}

TEST(FunctionTable, CodesWithoutARowDecodeAsRaw) {
    for (int code = 0; code < kExceptionBit; ++code) {
        const std::vector<std::uint8_t> pdu{static_cast<std::uint8_t>(code), 0x00, 0x00, 0x00,
                                            0x01};
        const auto request = decode_request(pdu);
        const bool raw = request && std::holds_alternative<RawRequest>(request.value());
        EXPECT_EQ(raw, find_function(static_cast<std::uint8_t>(code)) == nullptr) << code;
    }
}

TEST(FunctionTable, LookupFindsEveryRowByItsCode) {
    for (const FunctionRow& row : kFunctionTable) {
        const auto code = static_cast<std::uint8_t>(row.code);
        EXPECT_EQ(find_function(code), &row);
        EXPECT_EQ(function_name(code), row.name);
        EXPECT_EQ(find_function(code | kExceptionBit), nullptr);
    }
}

// The broadcast rule follows [SER]: what runs on broadcast is a write; FC 17 writes but reads too.
TEST(FunctionTable, OnlyWritesRunOnBroadcast) {
    for (const FunctionRow& row : kFunctionTable) {
        if (row.broadcast == Broadcast::Execute) {
            EXPECT_EQ(row.writes, Writes::Yes) << row.name;
        }
    }
    EXPECT_EQ(find_function(0x17)->broadcast, Broadcast::Ignore);
    EXPECT_EQ(find_function(0x17)->writes, Writes::Yes);
}

}  // namespace
}  // namespace mblab::protocol
