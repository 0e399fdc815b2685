#pragma once

#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "protocol/cursor.hpp"
#include "protocol/function_code.hpp"
#include "protocol/register_view.hpp"
#include "protocol/result.hpp"
#include "protocol/shared_fields.hpp"

// Request PDUs of every public function code. Decoded messages are views into the caller's
// buffer: they stay valid only while that buffer does. A decoded request has passed every check
// the PDU alone allows (quantities, byte counts, lengths), so handlers never see impossible values.
namespace mblab::protocol {

struct ReadBitsRequest {  // 01, 02
    FunctionCode function = FunctionCode::ReadCoils;
    std::uint16_t address = 0;
    std::uint16_t quantity = 0;
};

struct ReadRegistersRequest {  // 03, 04
    FunctionCode function = FunctionCode::ReadHoldingRegisters;
    std::uint16_t address = 0;
    std::uint16_t quantity = 0;
};

struct WriteSingleCoilRequest : AddressValue<FunctionCode::WriteSingleCoil> {
    bool on() const { return value == 0xFF00; }  // the value is 0x0000 or 0xFF00
};
struct WriteSingleRegisterRequest : AddressValue<FunctionCode::WriteSingleRegister> {};
struct ReadExceptionStatusRequest : CodeOnly<FunctionCode::ReadExceptionStatus> {};
struct DiagnosticsRequest : DiagnosticsFields {};
struct GetCommEventCounterRequest : CodeOnly<FunctionCode::GetCommEventCounter> {};
struct GetCommEventLogRequest : CodeOnly<FunctionCode::GetCommEventLog> {};

// 0F, 10: the starting address, the quantity, and the values as bits or registers.
template <FunctionCode Code, class Values>
struct WriteMultipleFields {
    static constexpr FunctionCode kFunction = Code;
    std::uint16_t address = 0;
    std::uint16_t quantity = 0;
    Values values;
};
struct WriteMultipleCoilsRequest : WriteMultipleFields<FunctionCode::WriteMultipleCoils, BitView> {
};
struct WriteMultipleRegistersRequest
    : WriteMultipleFields<FunctionCode::WriteMultipleRegisters, RegisterView> {};

struct ReportServerIdRequest : CodeOnly<FunctionCode::ReportServerId> {};

struct FileRecordRef {
    std::uint16_t file = 0;
    std::uint16_t record = 0;
    std::uint16_t length = 0;  // in registers
};

struct ReadFileRecordRequest {  // 14; sub-requests of 7 bytes each, already validated
    static constexpr FunctionCode kFunction = FunctionCode::ReadFileRecord;
    std::span<const std::uint8_t> sub_requests;
    std::size_t count() const { return sub_requests.size() / 7; }
    FileRecordRef at(std::size_t i) const;
};

struct FileRecordData {
    FileRecordRef ref;
    RegisterView data;
};

struct WriteFileRecordRequest : WriteFileRecordFields {
    // Walks the validated sub-requests; returns false after the last.
    bool next(std::size_t& offset, FileRecordData& out) const;
};

// Builders for the sub-request bytes that ReadFileRecordRequest / WriteFileRecordRequest view:
// write them into a scratch buffer, then point `sub_requests` at cursor.written().
// One FC 14 sub-request: reference type 6, file, record, length.
void encode_file_record_ref(WriteCursor& out, const FileRecordRef& ref);
// One FC 15 sub-request; the length field is taken from record.data, not record.ref.length.
void encode_file_record_data(WriteCursor& out, const FileRecordData& record);

struct MaskWriteRegisterRequest : MaskWriteFields {};

struct ReadWriteMultipleRegistersRequest {  // 17
    static constexpr FunctionCode kFunction = FunctionCode::ReadWriteMultipleRegisters;
    std::uint16_t read_address = 0;
    std::uint16_t read_quantity = 0;
    std::uint16_t write_address = 0;
    std::uint16_t write_quantity = 0;
    RegisterView values;
};

struct ReadFifoQueueRequest {  // 18
    static constexpr FunctionCode kFunction = FunctionCode::ReadFifoQueue;
    std::uint16_t address = 0;
};

struct ReadDeviceIdRequest {  // 2B / 0E
    static constexpr FunctionCode kFunction = FunctionCode::EncapsulatedInterface;
    std::uint8_t read_code = 1;  // 01 basic, 02 regular, 03 extended, 04 one object
    std::uint8_t object_id = 0;
};

struct EncapsulatedRequest : CanopenFields {};

// FC 5B, both directions: the fields up to the service code (CTP 7.13.1.4, 7.13.1.5). The
// fragment byte count counts every byte after it.
struct ObjectMessagingHeader {
    static constexpr FunctionCode kFunction = FunctionCode::ObjectMessaging;
    std::uint8_t fragment_byte_count = 0;
    std::uint8_t fragment_protocol = 0;
    std::uint16_t class_id = 0;
    std::uint16_t instance_id = 0;
    std::uint16_t service_code = 0;
};

struct ObjectMessagingRequest : ObjectMessagingHeader {  // 5B, CTP 7.13.1.4
    std::span<const std::uint8_t> parameters;
};

struct RawRequest : RawFields {};

#define MBLAB_REQUEST_TYPE(kind) kind##Request,
using Request = std::variant<MBLAB_MESSAGE_KINDS(MBLAB_REQUEST_TYPE) RawRequest>;
#undef MBLAB_REQUEST_TYPE

// Function code byte of any request.
std::uint8_t function_of(const Request& request);

// Decodes a whole request PDU (function code first). Checks run in the order of [APP]'s state
// diagrams: function (01: reserved MEI type or FC 08 sub-function), then lengths, counts and
// values (03), then ranges no device can hold (02: address + quantity past 0xFFFF; file record
// references outside type 6, file 1..FFFF, records 0..9999). Whether an address exists in a map
// is the device's job. Function codes without a type here decode to RawRequest (the device
// answers 01). The DecodeError names the wire field and the allowed range.
Result<Request> decode_request(std::span<const std::uint8_t> pdu);

// Writes the request PDU. Returns false when `out` ran out of space.
bool encode_request(const Request& request, WriteCursor& out);
// The PDU `request` encodes to; empty when it does not fit one.
std::vector<std::uint8_t> encoded_pdu(const Request& request);

}  // namespace mblab::protocol
