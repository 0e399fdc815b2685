// Response fields, both ways: the [APP] and seed example bytes decode to the fields the documents
// describe, and a message built from those fields encodes to the example bytes.
#include <gtest/gtest.h>

#include "pdu_fields_text.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;
using testing::ascii_hex;
using testing::encoded;
using testing::PduFields;

// One example a line.
// clang-format off
const testing::FieldsCase kExamples[] = {
    {"ReadCoils",                   "01 03 CD 6B 05",                               "ReadBitsResponse function=1 packed=[CD 6B 05]"},
    {"ReadHoldingRegisters",        "03 06 02 2B 00 00 00 64",                      "ReadRegistersResponse function=3 values=[022B 0000 0064]"},
    {"ReadInputRegisters",          "04 02 00 0A",                                  "ReadRegistersResponse function=4 values=[000A]"},
    {"WriteSingleCoilEcho",         "05 00 AC FF 00",                               "WriteSingleCoilResponse address=172 value=65280"},
    {"WriteSingleRegisterEcho",     "06 00 01 00 03",                               "WriteSingleRegisterResponse address=1 value=3"},
    {"ReadExceptionStatus",         "07 6D",                                        "ReadExceptionStatusResponse status=109"},
    {"DiagnosticsCounter",          "08 00 0B 01 08",                               "DiagnosticsResponse sub_function=11 data=[01 08]"},
    {"GetCommEventCounter",         "0B FF FF 01 08",                               "GetCommEventCounterResponse status=65535 event_count=264"},
    {"GetCommEventLog",             "0C 08 00 00 01 08 01 21 20 00",                "GetCommEventLogResponse status=0 event_count=264 message_count=289 events=[20 00]"},
    {"WriteMultipleCoilsEcho",      "0F 00 13 00 0A",                               "WriteMultipleCoilsResponse address=19 quantity=10"},
    {"WriteMultipleRegistersEcho",  "10 00 01 00 02",                               "WriteMultipleRegistersResponse address=1 quantity=2"},
    {"ReportServerId",              "11 03 2A FF 01",                               "ReportServerIdResponse data=[2A FF 01]"},
    {"WriteFileRecordEcho",         "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D", "WriteFileRecordResponse sub_requests=[06 00 04 00 07 00 03 06 AF 04 BE 10 0D]"},
    {"MaskWriteRegisterEcho",       "16 00 04 00 F2 00 25",                         "MaskWriteRegisterResponse address=4 and_mask=242 or_mask=37"},
    {"ReadWriteMultipleRegisters",  "17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF",    "ReadWriteMultipleRegistersResponse values=[00FE 0ACD 0001 0003 000D 00FF]"},
    {"ReadFifoQueue",               "18 00 06 00 02 01 B8 12 84",                   "ReadFifoQueueResponse values=[01B8 1284]"},
    {"ObjectMessagingSeed000",      "5B 0B 00 00 01 00 01 00 08 00 16 00 01",       "ObjectMessagingResponse fragment_byte_count=11 fragment_protocol=0 class_id=1 instance_id=1 service_code=8 error_code=22 parameters=[00 01]"},
    {"Exception",                   "83 02",                                        "ExceptionResponse function=3 code=2"},
    {"UnknownFunctionIsCarriedRaw", "41 01 02",                                     "RawResponse function=65 data=[01 02]"},
};
// clang-format on

// The test is test_request_fields.cpp's, run on responses.
INSTANTIATE_TEST_SUITE_P(Response, PduFields, ::testing::ValuesIn(testing::as_responses(kExamples)),
                         testing::fields_case_name);

TEST(ResponseFunction, ExceptionSetsTheHighBit) {
    EXPECT_EQ(function_of(Response{ExceptionResponse{0x2B, ExceptionCode::IllegalFunction}}), 0xAB);
}

TEST(ResponseWalks, ReadFileRecord) {
    const auto pdu = hex("14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40");
    const auto response = testing::decoded_as<ReadFileRecordResponse>(pdu, decode_response);
    std::size_t offset = 0;
    RegisterView group;
    ASSERT_TRUE(response.next(offset, group));
    ASSERT_EQ(group.size(), 2u);
    EXPECT_EQ(group[0], 0x0DFE);
    EXPECT_EQ(group[1], 0x0020);
    ASSERT_TRUE(response.next(offset, group));
    EXPECT_EQ(group[0], 0x33CD);
    EXPECT_EQ(group[1], 0x0040);
    EXPECT_FALSE(response.next(offset, group));

    const auto first = hex("0D FE 00 20");
    const auto second = hex("33 CD 00 40");
    std::array<std::uint8_t, 12> scratch{};
    WriteCursor subs(scratch);
    encode_file_record_sub_response(subs, RegisterView(first));
    encode_file_record_sub_response(subs, RegisterView(second));
    ASSERT_TRUE(subs.ok());
    EXPECT_EQ(encoded(ReadFileRecordResponse{subs.written()}), pdu);
}

TEST(ResponseWalks, ReadDeviceIdentification) {
    const auto pdu = hex("2B 0E 01 01 00 00 03 00 16" + ascii_hex("Company identification") +
                         "01 0F" + ascii_hex("Product code XX") + "02 05" + ascii_hex("V2.11"));
    const auto response = testing::decoded_as<ReadDeviceIdResponse>(pdu, decode_response);
    EXPECT_EQ(response.read_code, 1);
    EXPECT_EQ(response.conformity_level, 1);
    EXPECT_EQ(response.more_follows, 0);
    EXPECT_EQ(response.next_object_id, 0);
    EXPECT_EQ(response.object_count, 3);
    const char* const expected[] = {"Company identification", "Product code XX", "V2.11"};
    std::size_t offset = 0;
    DeviceIdObject object;
    for (std::uint8_t id = 0; id < 3; ++id) {
        ASSERT_TRUE(response.next(offset, object));
        EXPECT_EQ(object.id, id);
        EXPECT_EQ(std::string(object.value.begin(), object.value.end()), expected[id]);
    }
    EXPECT_FALSE(response.next(offset, object));

    std::array<std::uint8_t, 64> scratch{};
    WriteCursor objects(scratch);
    for (std::uint8_t id = 0; id < 3; ++id) {
        const std::string_view text = expected[id];
        const std::span<const std::uint8_t> value(
            reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
        ASSERT_TRUE(encode_device_id_object(objects, id, value));
    }
    EXPECT_EQ(encoded(ReadDeviceIdResponse{1, 1, 0, 0, 3, objects.written()}), pdu);
}

// A Latin-1 vendor name and a terminal escape: shown as \xNN, never as the raw bytes.
TEST(ResponseWalks, DeviceIdObjectTextShowsBytesThatAreNotPrintableAsciiAsEscapes) {
    const auto value = hex("4D FC 6C 6C 65 72 1B 5B 32 4A 5C 7F 00");
    const DeviceIdObject object{0, value};
    EXPECT_EQ(object.text(), R"(M\xFCller\x1B[2J\\\x7F\x00)");
}

TEST(ResponseWalks, DeviceIdObjectLongerThan255BytesIsRefused) {
    const std::vector<std::uint8_t> value(256, 'x');
    std::array<std::uint8_t, 300> scratch{};
    WriteCursor out(scratch);
    EXPECT_FALSE(encode_device_id_object(out, 0x80, value));
}

TEST(ResponseWalks, EncodeExceptionSetsTheHighBit) {
    std::array<std::uint8_t, 2> buffer{};
    WriteCursor out(buffer);
    ASSERT_TRUE(encode_exception(0x25, ExceptionCode::IllegalFunction, out));
    EXPECT_EQ(to_hex(out.written()), "A5 01");
    WriteCursor too_small(std::span<std::uint8_t>(buffer).first(1));
    EXPECT_FALSE(encode_exception(0x25, ExceptionCode::IllegalFunction, too_small));
}

}  // namespace
}  // namespace mblab::protocol
