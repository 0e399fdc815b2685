#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <variant>

#include "protocol/cursor.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/register_view.hpp"
#include "protocol/request.hpp"
#include "protocol/result.hpp"
#include "protocol/shared_fields.hpp"

// Response PDUs of every public function code, as views into the caller's buffer.
namespace mblab::protocol {

struct ReadBitsResponse {  // 01, 02: byte count then packed bits
    FunctionCode function = FunctionCode::ReadCoils;
    std::span<const std::uint8_t> packed;
};

struct ReadRegistersResponse {  // 03, 04
    FunctionCode function = FunctionCode::ReadHoldingRegisters;
    RegisterView values;
};

// Echoes of the address and value written.
struct WriteSingleCoilResponse : AddressValue<FunctionCode::WriteSingleCoil> {};
struct WriteSingleRegisterResponse : AddressValue<FunctionCode::WriteSingleRegister> {};

struct ReadExceptionStatusResponse {  // 07
    static constexpr FunctionCode kFunction = FunctionCode::ReadExceptionStatus;
    std::uint8_t status = 0;
};

struct DiagnosticsResponse : DiagnosticsFields {};

struct GetCommEventCounterResponse {  // 0B
    static constexpr FunctionCode kFunction = FunctionCode::GetCommEventCounter;
    std::uint16_t status = 0;
    std::uint16_t event_count = 0;
};

struct GetCommEventLogResponse {  // 0C
    static constexpr FunctionCode kFunction = FunctionCode::GetCommEventLog;
    std::uint16_t status = 0;
    std::uint16_t event_count = 0;
    std::uint16_t message_count = 0;
    std::span<const std::uint8_t> events;  // at most 64
};

// Echoes of the starting address and quantity.
struct WriteMultipleCoilsResponse : AddressQuantity<FunctionCode::WriteMultipleCoils> {};
struct WriteMultipleRegistersResponse : AddressQuantity<FunctionCode::WriteMultipleRegisters> {};

struct ReportServerIdResponse {  // 11: server id, run indicator, extra data (device specific)
    static constexpr FunctionCode kFunction = FunctionCode::ReportServerId;
    std::span<const std::uint8_t> data;
};

struct ReadFileRecordResponse {  // 14: sub-responses (length, reference type 6, data)
    static constexpr FunctionCode kFunction = FunctionCode::ReadFileRecord;
    std::span<const std::uint8_t> sub_responses;
    // Walks the validated sub-responses; returns false after the last.
    bool next(std::size_t& offset, RegisterView& out) const;
};

// Builds one FC 14 sub-response (length, reference type 6, registers) into a scratch buffer
// that ReadFileRecordResponse::sub_responses then views.
void encode_file_record_sub_response(WriteCursor& out, RegisterView data);

struct WriteFileRecordResponse : WriteFileRecordFields {};  // echo of the request

struct MaskWriteRegisterResponse : MaskWriteFields {};  // echo

struct ReadWriteMultipleRegistersResponse {  // 17
    static constexpr FunctionCode kFunction = FunctionCode::ReadWriteMultipleRegisters;
    RegisterView values;
};

struct ReadFifoQueueResponse {  // 18
    static constexpr FunctionCode kFunction = FunctionCode::ReadFifoQueue;
    RegisterView values;
};

struct DeviceIdObject {
    std::uint8_t id = 0;
    std::span<const std::uint8_t> value;

    // The value as text (support/escaped_text.hpp): the basic and regular objects are ASCII
    // strings (MB App Protocol 6.21), but nothing makes a device send them so.
    std::string text() const;
};

struct ReadDeviceIdResponse {  // 2B / 0E
    static constexpr FunctionCode kFunction = FunctionCode::EncapsulatedInterface;
    std::uint8_t read_code = 1;
    std::uint8_t conformity_level = 0;
    std::uint8_t more_follows = 0;
    std::uint8_t next_object_id = 0;
    std::uint8_t object_count = 0;
    std::span<const std::uint8_t> objects;  // validated id / length / value triples
    // Walks the objects; returns false after the last.
    bool next(std::size_t& offset, DeviceIdObject& out) const;
};

// Builds one id / length / value triple for ReadDeviceIdResponse::objects. Returns false when
// the value is longer than 255 bytes or `out` ran out of space.
bool encode_device_id_object(WriteCursor& out, std::uint8_t id,
                             std::span<const std::uint8_t> value);

struct EncapsulatedResponse : CanopenFields {};

struct ObjectMessagingResponse : ObjectMessagingHeader {  // 5B, CTP 7.13.1.5
    std::uint16_t error_code = 0;                         // 00 00 for service data
    std::span<const std::uint8_t> parameters;
};

struct ExceptionResponse {
    std::uint8_t function = 0;  // the request's code, without the 0x80 bit
    ExceptionCode code = ExceptionCode::IllegalFunction;
};

struct RawResponse : RawFields {};

#define MBLAB_RESPONSE_TYPE(kind) kind##Response,
using Response =
    std::variant<MBLAB_MESSAGE_KINDS(MBLAB_RESPONSE_TYPE) ExceptionResponse, RawResponse>;
#undef MBLAB_RESPONSE_TYPE

// Function code byte of any response as it goes on the wire (with 0x80 for an exception).
std::uint8_t function_of(const Response& response);

// Decodes a whole response PDU; an exception response (code | 0x80) becomes ExceptionResponse.
// Strict, for clients facing hostile servers: every count must match the bytes present and every
// field stay inside [APP]'s ranges. Whether the answer fits the request is the caller's check.
Result<Response> decode_response(std::span<const std::uint8_t> pdu);

// Writes the response PDU. Returns false when `out` ran out of space.
bool encode_response(const Response& response, WriteCursor& out);

// Writes the two-byte exception PDU for a request's function code.
bool encode_exception(std::uint8_t function, ExceptionCode code, WriteCursor& out);

}  // namespace mblab::protocol
