// Response fields, both ways: the [APP] and seed example bytes decode to the fields the documents
// describe, and a message built from those fields encodes to the example bytes.
#include <gtest/gtest.h>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;
using testing::ascii_hex;
using testing::encoded;

template <class Message>
Message decoded_as(const std::vector<std::uint8_t>& pdu) {
    return testing::decoded_as<Message>(pdu, decode_response);
}

TEST(ResponseFields, ReadCoils) {
    const auto pdu = hex("01 03 CD 6B 05");
    const auto response = decoded_as<ReadBitsResponse>(pdu);
    EXPECT_EQ(response.function, FunctionCode::ReadCoils);
    EXPECT_EQ(to_hex(response.packed), "CD 6B 05");
    const auto packed = hex("CD 6B 05");
    EXPECT_EQ(encoded(ReadBitsResponse{FunctionCode::ReadCoils, packed}), pdu);
}

TEST(ResponseFields, ReadHoldingRegisters) {
    const auto pdu = hex("03 06 02 2B 00 00 00 64");
    const auto response = decoded_as<ReadRegistersResponse>(pdu);
    EXPECT_EQ(response.function, FunctionCode::ReadHoldingRegisters);
    ASSERT_EQ(response.values.size(), 3u);
    EXPECT_EQ(response.values[0], 555);
    EXPECT_EQ(response.values[1], 0);
    EXPECT_EQ(response.values[2], 100);
    const auto values = hex("02 2B 00 00 00 64");
    EXPECT_EQ(
        encoded(ReadRegistersResponse{FunctionCode::ReadHoldingRegisters, RegisterView(values)}),
        pdu);
}

TEST(ResponseFields, ReadInputRegisters) {
    const auto pdu = hex("04 02 00 0A");
    const auto response = decoded_as<ReadRegistersResponse>(pdu);
    EXPECT_EQ(response.function, FunctionCode::ReadInputRegisters);
    EXPECT_EQ(response.values[0], 10);
}

TEST(ResponseFields, WriteEchoes) {
    EXPECT_EQ(decoded_as<WriteSingleCoilResponse>(hex("05 00 AC FF 00")).value, 0xFF00);
    EXPECT_EQ(encoded(WriteSingleCoilResponse{0xAC, 0xFF00}), hex("05 00 AC FF 00"));
    EXPECT_EQ(decoded_as<WriteSingleRegisterResponse>(hex("06 00 01 00 03")).value, 3);
    EXPECT_EQ(encoded(WriteSingleRegisterResponse{1, 3}), hex("06 00 01 00 03"));
    EXPECT_EQ(decoded_as<WriteMultipleCoilsResponse>(hex("0F 00 13 00 0A")).quantity, 10);
    EXPECT_EQ(encoded(WriteMultipleCoilsResponse{0x13, 10}), hex("0F 00 13 00 0A"));
    EXPECT_EQ(decoded_as<WriteMultipleRegistersResponse>(hex("10 00 01 00 02")).address, 1);
    EXPECT_EQ(encoded(WriteMultipleRegistersResponse{1, 2}), hex("10 00 01 00 02"));
    const auto mask = decoded_as<MaskWriteRegisterResponse>(hex("16 00 04 00 F2 00 25"));
    EXPECT_EQ(mask.and_mask, 0xF2);
    EXPECT_EQ(mask.or_mask, 0x25);
    EXPECT_EQ(encoded(MaskWriteRegisterResponse{4, 0xF2, 0x25}), hex("16 00 04 00 F2 00 25"));
}

TEST(ResponseFields, ReadExceptionStatus) {
    EXPECT_EQ(decoded_as<ReadExceptionStatusResponse>(hex("07 6D")).status, 0x6D);
    EXPECT_EQ(encoded(ReadExceptionStatusResponse{0x6D}), hex("07 6D"));
}

TEST(ResponseFields, DiagnosticsCounter) {
    const auto pdu = hex("08 00 0B 01 08");
    const auto response = decoded_as<DiagnosticsResponse>(pdu);
    EXPECT_EQ(response.sub_function, 0x0B);
    EXPECT_EQ(to_hex(response.data), "01 08");
    const auto data = hex("01 08");
    EXPECT_EQ(encoded(DiagnosticsResponse{0x0B, data}), pdu);
}

TEST(ResponseFields, GetCommEventCounter) {
    const auto response = decoded_as<GetCommEventCounterResponse>(hex("0B FF FF 01 08"));
    EXPECT_EQ(response.status, 0xFFFF);
    EXPECT_EQ(response.event_count, 264);
    EXPECT_EQ(encoded(GetCommEventCounterResponse{0xFFFF, 264}), hex("0B FF FF 01 08"));
}

TEST(ResponseFields, GetCommEventLog) {
    const auto pdu = hex("0C 08 00 00 01 08 01 21 20 00");
    const auto response = decoded_as<GetCommEventLogResponse>(pdu);
    EXPECT_EQ(response.status, 0);
    EXPECT_EQ(response.event_count, 264);
    EXPECT_EQ(response.message_count, 289);
    EXPECT_EQ(to_hex(response.events), "20 00");
    const auto events = hex("20 00");
    EXPECT_EQ(encoded(GetCommEventLogResponse{0, 264, 289, events}), pdu);
}

TEST(ResponseFields, ReportServerId) {
    const auto pdu = hex("11 03 2A FF 01");
    EXPECT_EQ(to_hex(decoded_as<ReportServerIdResponse>(pdu).data), "2A FF 01");
    const auto data = hex("2A FF 01");
    EXPECT_EQ(encoded(ReportServerIdResponse{data}), pdu);
}

TEST(ResponseFields, ReadFileRecord) {
    const auto pdu = hex("14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40");
    const auto response = decoded_as<ReadFileRecordResponse>(pdu);
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

TEST(ResponseFields, WriteFileRecordEcho) {
    const auto pdu = hex("15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D");
    const auto response = decoded_as<WriteFileRecordResponse>(pdu);
    EXPECT_EQ(response.sub_requests.size(), 13u);
    EXPECT_EQ(encoded(WriteFileRecordResponse{response.sub_requests}), pdu);
}

TEST(ResponseFields, ReadWriteMultipleRegisters) {
    const auto pdu = hex("17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF");
    const auto response = decoded_as<ReadWriteMultipleRegistersResponse>(pdu);
    ASSERT_EQ(response.values.size(), 6u);
    EXPECT_EQ(response.values[0], 0x00FE);
    EXPECT_EQ(response.values[5], 0x00FF);
    const auto values = hex("00 FE 0A CD 00 01 00 03 00 0D 00 FF");
    EXPECT_EQ(encoded(ReadWriteMultipleRegistersResponse{RegisterView(values)}), pdu);
}

TEST(ResponseFields, ReadFifoQueue) {
    const auto pdu = hex("18 00 06 00 02 01 B8 12 84");
    const auto response = decoded_as<ReadFifoQueueResponse>(pdu);
    ASSERT_EQ(response.values.size(), 2u);
    EXPECT_EQ(response.values[0], 440);
    EXPECT_EQ(response.values[1], 4740);
    const auto values = hex("01 B8 12 84");
    EXPECT_EQ(encoded(ReadFifoQueueResponse{RegisterView(values)}), pdu);
}

TEST(ResponseFields, ReadDeviceIdentification) {
    const auto pdu = hex("2B 0E 01 01 00 00 03 00 16" + ascii_hex("Company identification") +
                         "01 0F" + ascii_hex("Product code XX") + "02 05" + ascii_hex("V2.11"));
    const auto response = decoded_as<ReadDeviceIdResponse>(pdu);
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

TEST(ResponseFields, DeviceIdObjectLongerThan255BytesIsRefused) {
    const std::vector<std::uint8_t> value(256, 'x');
    std::array<std::uint8_t, 300> scratch{};
    WriteCursor out(scratch);
    EXPECT_FALSE(encode_device_id_object(out, 0x80, value));
}

TEST(ResponseFields, ObjectMessagingSeed000) {
    const auto pdu = hex("5B 0B 00 00 01 00 01 00 08 00 16 00 01");
    const auto response = decoded_as<ObjectMessagingResponse>(pdu);
    EXPECT_EQ(response.fragment_byte_count, 0x0B);
    EXPECT_EQ(response.class_id, 1);
    EXPECT_EQ(response.instance_id, 1);
    EXPECT_EQ(response.service_code, 8);
    EXPECT_EQ(response.error_code, 0x16);
    EXPECT_EQ(to_hex(response.parameters), "00 01");
    const auto parameters = hex("00 01");
    EXPECT_EQ(encoded(ObjectMessagingResponse{0, 0, 1, 1, 8, 0x16, parameters}), pdu);
}

TEST(ResponseFields, Exception) {
    const auto response = decoded_as<ExceptionResponse>(hex("83 02"));
    EXPECT_EQ(response.function, 0x03);
    EXPECT_EQ(response.code, ExceptionCode::IllegalDataAddress);
    EXPECT_EQ(encoded(ExceptionResponse{0x03, ExceptionCode::IllegalDataAddress}), hex("83 02"));
    EXPECT_EQ(function_of(Response{ExceptionResponse{0x2B, ExceptionCode::IllegalFunction}}), 0xAB);
}

TEST(ResponseFields, EncodeExceptionSetsTheHighBit) {
    std::array<std::uint8_t, 2> buffer{};
    WriteCursor out(buffer);
    ASSERT_TRUE(encode_exception(0x25, ExceptionCode::IllegalFunction, out));
    EXPECT_EQ(to_hex(out.written()), "A5 01");
    WriteCursor too_small(std::span<std::uint8_t>(buffer).first(1));
    EXPECT_FALSE(encode_exception(0x25, ExceptionCode::IllegalFunction, too_small));
}

TEST(ResponseFields, UnknownFunctionIsCarriedRaw) {
    const auto pdu = hex("41 01 02");
    const auto response = decoded_as<RawResponse>(pdu);
    EXPECT_EQ(response.function, 0x41);
    EXPECT_EQ(to_hex(response.data), "01 02");
}

}  // namespace
}  // namespace mblab::protocol
