// Request fields, both ways: the [APP] example bytes decode to the fields the spec describes, and
// a message built from those fields encodes to the example bytes.
#include <gtest/gtest.h>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;
using testing::encoded;

template <class Message>
Message decoded_as(const std::vector<std::uint8_t>& pdu) {
    return testing::decoded_as<Message>(pdu, decode_request);
}

TEST(RequestFields, ReadCoils) {
    const auto pdu = hex("01 00 13 00 13");
    const auto request = decoded_as<ReadBitsRequest>(pdu);
    EXPECT_EQ(request.function, FunctionCode::ReadCoils);
    EXPECT_EQ(request.address, 0x13);
    EXPECT_EQ(request.quantity, 19);
    EXPECT_EQ(encoded(ReadBitsRequest{FunctionCode::ReadCoils, 0x13, 19}), pdu);
}

TEST(RequestFields, ReadDiscreteInputs) {
    const auto pdu = hex("02 00 C4 00 16");
    const auto request = decoded_as<ReadBitsRequest>(pdu);
    EXPECT_EQ(request.function, FunctionCode::ReadDiscreteInputs);
    EXPECT_EQ(request.address, 196);
    EXPECT_EQ(request.quantity, 22);
    EXPECT_EQ(encoded(ReadBitsRequest{FunctionCode::ReadDiscreteInputs, 196, 22}), pdu);
}

TEST(RequestFields, ReadHoldingRegisters) {
    const auto pdu = hex("03 00 6B 00 03");
    const auto request = decoded_as<ReadRegistersRequest>(pdu);
    EXPECT_EQ(request.function, FunctionCode::ReadHoldingRegisters);
    EXPECT_EQ(request.address, 107);
    EXPECT_EQ(request.quantity, 3);
    EXPECT_EQ(encoded(ReadRegistersRequest{FunctionCode::ReadHoldingRegisters, 107, 3}), pdu);
}

TEST(RequestFields, ReadInputRegisters) {
    const auto pdu = hex("04 00 08 00 01");
    const auto request = decoded_as<ReadRegistersRequest>(pdu);
    EXPECT_EQ(request.function, FunctionCode::ReadInputRegisters);
    EXPECT_EQ(request.address, 8);
    EXPECT_EQ(request.quantity, 1);
    EXPECT_EQ(encoded(ReadRegistersRequest{FunctionCode::ReadInputRegisters, 8, 1}), pdu);
}

TEST(RequestFields, WriteSingleCoil) {
    const auto pdu = hex("05 00 AC FF 00");
    const auto request = decoded_as<WriteSingleCoilRequest>(pdu);
    EXPECT_EQ(request.address, 172);
    EXPECT_TRUE(request.on());
    EXPECT_EQ(encoded(WriteSingleCoilRequest{172, 0xFF00}), pdu);
    EXPECT_FALSE(decoded_as<WriteSingleCoilRequest>(hex("05 00 AC 00 00")).on());
}

TEST(RequestFields, WriteSingleRegister) {
    const auto pdu = hex("06 00 01 00 03");
    const auto request = decoded_as<WriteSingleRegisterRequest>(pdu);
    EXPECT_EQ(request.address, 1);
    EXPECT_EQ(request.value, 3);
    EXPECT_EQ(encoded(WriteSingleRegisterRequest{1, 3}), pdu);
}

TEST(RequestFields, RequestsWithoutData) {
    decoded_as<ReadExceptionStatusRequest>(hex("07"));
    decoded_as<GetCommEventCounterRequest>(hex("0B"));
    decoded_as<GetCommEventLogRequest>(hex("0C"));
    decoded_as<ReportServerIdRequest>(hex("11"));
    EXPECT_EQ(encoded(ReadExceptionStatusRequest{}), hex("07"));
    EXPECT_EQ(encoded(GetCommEventCounterRequest{}), hex("0B"));
    EXPECT_EQ(encoded(GetCommEventLogRequest{}), hex("0C"));
    EXPECT_EQ(encoded(ReportServerIdRequest{}), hex("11"));
}

TEST(RequestFields, DiagnosticsReturnQueryData) {
    const auto pdu = hex("08 00 00 A5 37");
    const auto request = decoded_as<DiagnosticsRequest>(pdu);
    EXPECT_EQ(request.sub_function, 0);
    EXPECT_EQ(to_hex(request.data), "A5 37");
    const auto data = hex("A5 37");
    EXPECT_EQ(encoded(DiagnosticsRequest{0, data}), pdu);
}

TEST(RequestFields, WriteMultipleCoils) {
    const auto pdu = hex("0F 00 13 00 0A 02 CD 01");
    const auto request = decoded_as<WriteMultipleCoilsRequest>(pdu);
    EXPECT_EQ(request.address, 19);
    EXPECT_EQ(request.quantity, 10);
    ASSERT_EQ(request.values.size(), 10u);
    // CD 01: outputs 20..27 = 1 0 1 1 0 0 1 1 (LSB first), 28 = 1, 29 = 0.
    const bool expected[] = {true, false, true, true, false, false, true, true, true, false};
    for (std::size_t i = 0; i < 10; ++i)
        EXPECT_EQ(request.values[i], expected[i]) << i;
    const auto packed = hex("CD 01");
    EXPECT_EQ(encoded(WriteMultipleCoilsRequest{19, 10, BitView(packed, 10)}), pdu);
}

TEST(RequestFields, WriteMultipleRegisters) {
    const auto pdu = hex("10 00 01 00 02 04 00 0A 01 02");
    const auto request = decoded_as<WriteMultipleRegistersRequest>(pdu);
    EXPECT_EQ(request.address, 1);
    EXPECT_EQ(request.quantity, 2);
    ASSERT_EQ(request.values.size(), 2u);
    EXPECT_EQ(request.values[0], 0x000A);
    EXPECT_EQ(request.values[1], 0x0102);
    const auto values = hex("00 0A 01 02");
    EXPECT_EQ(encoded(WriteMultipleRegistersRequest{1, 2, RegisterView(values)}), pdu);
}

TEST(RequestFields, ReadFileRecord) {
    const auto pdu = hex("14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02");
    const auto request = decoded_as<ReadFileRecordRequest>(pdu);
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

TEST(RequestFields, WriteFileRecord) {
    const auto pdu = hex("15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D");
    const auto request = decoded_as<WriteFileRecordRequest>(pdu);
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

TEST(RequestFields, MaskWriteRegister) {
    const auto pdu = hex("16 00 04 00 F2 00 25");
    const auto request = decoded_as<MaskWriteRegisterRequest>(pdu);
    EXPECT_EQ(request.address, 4);
    EXPECT_EQ(request.and_mask, 0x00F2);
    EXPECT_EQ(request.or_mask, 0x0025);
    EXPECT_EQ(encoded(MaskWriteRegisterRequest{4, 0xF2, 0x25}), pdu);
}

TEST(RequestFields, ReadWriteMultipleRegisters) {
    const auto pdu = hex("17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF");
    const auto request = decoded_as<ReadWriteMultipleRegistersRequest>(pdu);
    EXPECT_EQ(request.read_address, 3);
    EXPECT_EQ(request.read_quantity, 6);
    EXPECT_EQ(request.write_address, 14);
    EXPECT_EQ(request.write_quantity, 3);
    ASSERT_EQ(request.values.size(), 3u);
    EXPECT_EQ(request.values[2], 0x00FF);
    const auto values = hex("00 FF 00 FF 00 FF");
    EXPECT_EQ(encoded(ReadWriteMultipleRegistersRequest{3, 6, 14, 3, RegisterView(values)}), pdu);
}

TEST(RequestFields, ReadFifoQueue) {
    const auto pdu = hex("18 04 DE");
    EXPECT_EQ(decoded_as<ReadFifoQueueRequest>(pdu).address, 1246);
    EXPECT_EQ(encoded(ReadFifoQueueRequest{1246}), pdu);
}

TEST(RequestFields, ReadDeviceIdentification) {
    const auto pdu = hex("2B 0E 04 02");
    const auto request = decoded_as<ReadDeviceIdRequest>(pdu);
    EXPECT_EQ(request.read_code, 4);
    EXPECT_EQ(request.object_id, 2);
    EXPECT_EQ(encoded(ReadDeviceIdRequest{4, 2}), pdu);
}

TEST(RequestFields, CanopenGeneralReferenceIsOpaque) {
    const auto pdu = hex("2B 0D 01 02 03");
    const auto request = decoded_as<EncapsulatedRequest>(pdu);
    EXPECT_EQ(request.mei_type, kMeiCanopen);
    EXPECT_EQ(to_hex(request.data), "01 02 03");
    const auto data = hex("01 02 03");
    EXPECT_EQ(encoded(EncapsulatedRequest{kMeiCanopen, data}), pdu);
}

TEST(RequestFields, ObjectMessagingSeed000) {
    const auto pdu = hex("5B 09 00 00 01 00 01 00 07 00 01");
    const auto request = decoded_as<ObjectMessagingRequest>(pdu);
    EXPECT_EQ(request.fragment_byte_count, 9);
    EXPECT_EQ(request.fragment_protocol, 0);
    EXPECT_EQ(request.class_id, 1);
    EXPECT_EQ(request.instance_id, 1);
    EXPECT_EQ(request.service_code, 7);
    EXPECT_EQ(to_hex(request.parameters), "00 01");
    // The encoder derives the fragment byte count from the parameters.
    const auto parameters = hex("00 01");
    EXPECT_EQ(encoded(ObjectMessagingRequest{0, 0, 1, 1, 7, parameters}), pdu);
}

TEST(RequestFields, UnknownFunctionIsCarriedRaw) {
    const auto pdu = hex("25 00 01 00 01");
    const auto request = decoded_as<RawRequest>(pdu);
    EXPECT_EQ(request.function, 0x25);
    EXPECT_EQ(to_hex(request.data), "00 01 00 01");
    const auto data = hex("00 01 00 01");
    EXPECT_EQ(encoded(RawRequest{0x25, data}), pdu);
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
