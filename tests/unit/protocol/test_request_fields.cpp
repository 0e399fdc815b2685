// Request fields, both ways: the [APP] example bytes decode to the fields the spec describes, and
// a message built from those fields encodes to the example bytes.
#include <gtest/gtest.h>

#include "pdu_fields_text.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using testing::encoded;
using testing::PduFields;

// CD 01 packs outputs 20..27 = 1 0 1 1 0 0 1 1 (LSB first), 28 = 1, 29 = 0.
// One example a line.
// clang-format off
const testing::FieldsCase kExamples[] = {
    {"ReadCoils",                       "01 00 13 00 13",                                  "ReadBitsRequest function=1 address=19 quantity=19"},
    {"ReadDiscreteInputs",              "02 00 C4 00 16",                                  "ReadBitsRequest function=2 address=196 quantity=22"},
    {"ReadHoldingRegisters",            "03 00 6B 00 03",                                  "ReadRegistersRequest function=3 address=107 quantity=3"},
    {"ReadInputRegisters",              "04 00 08 00 01",                                  "ReadRegistersRequest function=4 address=8 quantity=1"},
    {"WriteSingleCoil",                 "05 00 AC FF 00",                                  "WriteSingleCoilRequest address=172 value=65280 on=1"},
    {"WriteSingleCoilOff",              "05 00 AC 00 00",                                  "WriteSingleCoilRequest address=172 value=0 on=0"},
    {"WriteSingleRegister",             "06 00 01 00 03",                                  "WriteSingleRegisterRequest address=1 value=3"},
    {"ReadExceptionStatus",             "07",                                              "ReadExceptionStatusRequest"},
    {"DiagnosticsReturnQueryData",      "08 00 00 A5 37",                                  "DiagnosticsRequest sub_function=0 data=[A5 37]"},
    {"GetCommEventCounter",             "0B",                                              "GetCommEventCounterRequest"},
    {"GetCommEventLog",                 "0C",                                              "GetCommEventLogRequest"},
    {"WriteMultipleCoils",              "0F 00 13 00 0A 02 CD 01",                         "WriteMultipleCoilsRequest address=19 quantity=10 values=1011001110"},
    {"WriteMultipleRegisters",          "10 00 01 00 02 04 00 0A 01 02",                   "WriteMultipleRegistersRequest address=1 quantity=2 values=[000A 0102]"},
    {"ReportServerId",                  "11",                                              "ReportServerIdRequest"},
    {"MaskWriteRegister",               "16 00 04 00 F2 00 25",                            "MaskWriteRegisterRequest address=4 and_mask=242 or_mask=37"},
    {"ReadWriteMultipleRegisters",      "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF", "ReadWriteMultipleRegistersRequest read_address=3 read_quantity=6 write_address=14 write_quantity=3 values=[00FF 00FF 00FF]"},
    {"ReadFifoQueue",                   "18 04 DE",                                        "ReadFifoQueueRequest address=1246"},
    {"ReadDeviceIdentification",        "2B 0E 04 02",                                     "ReadDeviceIdRequest read_code=4 object_id=2"},
    {"CanopenGeneralReferenceIsOpaque", "2B 0D 01 02 03",                                  "EncapsulatedRequest mei_type=13 data=[01 02 03]"},
    {"ObjectMessagingSeed000",          "5B 09 00 00 01 00 01 00 07 00 01",                "ObjectMessagingRequest fragment_byte_count=9 fragment_protocol=0 class_id=1 instance_id=1 service_code=7 parameters=[00 01]"},
    {"UnknownFunctionIsCarriedRaw",     "25 00 01 00 01",                                  "RawRequest function=37 data=[00 01 00 01]"},
};
// clang-format on

// The decoded fields are checked by name; a message with them encodes back to the example.
TEST_P(PduFields, DecodeAndEncode) {
    if (GetParam().response) {
        testing::expect_fields(GetParam(), decode_response);
    } else {
        testing::expect_fields(GetParam(), decode_request);
    }
}

INSTANTIATE_TEST_SUITE_P(Request, PduFields, ::testing::ValuesIn(kExamples),
                         testing::fields_case_name);

// Both built with a fragment byte count of 0: the encoder derives it from the parameters.
TEST(PduEncode, ObjectMessagingDerivesTheFragmentByteCount) {
    const auto parameters = hex("00 01");
    EXPECT_EQ(encoded(ObjectMessagingRequest{{0, 0, 1, 1, 7}, parameters}),
              hex("5B 09 00 00 01 00 01 00 07 00 01"));
    EXPECT_EQ(encoded(ObjectMessagingResponse{{0, 0, 1, 1, 8}, 0x16, parameters}),
              hex("5B 0B 00 00 01 00 01 00 08 00 16 00 01"));
}

TEST(RequestFileRecords, ReadFileRecord) {
    const auto pdu = hex("14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02");
    const auto request = testing::decoded_as<ReadFileRecordRequest>(pdu, decode_request);
    ASSERT_EQ(request.count(), 2u);
    EXPECT_EQ(request.at(0).file, 4);
    EXPECT_EQ(request.at(0).record, 1);
    EXPECT_EQ(request.at(0).length, 2);
    EXPECT_EQ(request.at(1).file, 3);
    EXPECT_EQ(request.at(1).record, 9);
    EXPECT_EQ(request.at(1).length, 2);

    std::array<std::uint8_t, 14> scratch{};
    WriteCursor subs(scratch);
    encode_file_record_ref(subs, {4, 1, 2});
    encode_file_record_ref(subs, {3, 9, 2});
    ASSERT_TRUE(subs.ok());
    EXPECT_EQ(encoded(ReadFileRecordRequest{subs.written()}), pdu);
}

TEST(RequestFileRecords, WriteFileRecord) {
    const auto pdu = hex("15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D");
    const auto request = testing::decoded_as<WriteFileRecordRequest>(pdu, decode_request);
    std::size_t offset = 0;
    FileRecordData record;
    ASSERT_TRUE(request.next(offset, record));
    EXPECT_EQ(record.ref.file, 4);
    EXPECT_EQ(record.ref.record, 7);
    EXPECT_EQ(record.ref.length, 3);
    ASSERT_EQ(record.data.size(), 3u);
    EXPECT_EQ(record.data[0], 0x06AF);
    EXPECT_EQ(record.data[1], 0x04BE);
    EXPECT_EQ(record.data[2], 0x100D);
    EXPECT_FALSE(request.next(offset, record));

    const auto values = hex("06 AF 04 BE 10 0D");
    std::array<std::uint8_t, 13> scratch{};
    WriteCursor subs(scratch);
    encode_file_record_data(subs, {{4, 7, 0}, RegisterView(values)});
    ASSERT_TRUE(subs.ok());
    EXPECT_EQ(encoded(WriteFileRecordRequest{subs.written()}), pdu);
}

TEST(RequestEncode, ReportsLackOfSpace) {
    std::array<std::uint8_t, 4> small{};
    WriteCursor out(small);
    EXPECT_FALSE(
        encode_request(ReadRegistersRequest{FunctionCode::ReadHoldingRegisters, 0, 1}, out));
}

TEST(RequestEncode, RefusesACountThatDoesNotFitItsByte) {
    const std::vector<std::uint8_t> too_many(256, 0);
    std::array<std::uint8_t, 512> big{};
    WriteCursor out(big);
    EXPECT_FALSE(
        encode_request(WriteMultipleRegistersRequest{0, 128, RegisterView(too_many)}, out));
}

}  // namespace
}  // namespace mblab::protocol
