#include "protocol/device_id.hpp"
#include "protocol/file_record.hpp"
#include "protocol/function_dispatch.hpp"
#include "protocol/limits.hpp"
#include "protocol/message_checks.hpp"
#include "protocol/response.hpp"

// Responses are decoded as strictly as requests: a client must never trust a count from the
// wire (CVE-2023-26793: a malicious answer overflowed a client's buffer). Every count must match
// the bytes present, and every field stays inside the ranges of [APP].
namespace mblab::protocol {

namespace {

using detail::FieldReader;
using detail::value_error;

constexpr std::size_t kEventLogHeader = 6;  // status, event count, message count

constexpr detail::CountRule kPackedBitsCount{
    "byte count", 1, detail::packed_size(limits::kMaxReadBits), 1, "must be 1..250"};
constexpr detail::CountRule kRegistersCount{"byte count", 2, 2 * limits::kMaxReadRegisters, 2,
                                            "must be even, 2..250 (1..125 registers)"};
constexpr detail::CountRule kServerIdCount{
    "byte count", 1, 0xFF, 1, "must be 1 or more (server id, run indicator, additional data)"};

// 03, 04, 17: a byte count, then registers.
template <class Message>
Result<Response> decode_registers(FieldReader& in, Message response) {
    std::span<const std::uint8_t> values;
    in.counted_rest(kRegistersCount, values);
    response.values = RegisterView(values);
    return detail::finish<Response>(in, response);
}

// 0F, 10: the echo of the starting address and quantity.
template <class Message>
Result<Response> decode_write_multiple(FieldReader& in, const detail::QuantityLimit& limit) {
    Message response;
    in.u16(response.address, "starting address").u16(response.quantity, "quantity").end();
    detail::check_quantity(in, response.quantity, limit);
    detail::check_address_span(in, response.address, response.quantity, "starting address");
    return detail::finish<Response>(in, response);
}

Result<Response> decode_read_device_id(FieldReader& in) {
    ReadDeviceIdResponse response;
    in.u8(response.read_code, "read device id code")
        .u8(response.conformity_level, "conformity level")
        .u8(response.more_follows, "more follows")
        .u8(response.next_object_id, "next object id")
        .u8(response.object_count, "number of objects")
        .rest(response.objects);
    if (in.ok()) {
        detail::check_read_device_id_response(in,
                                              {response.read_code, response.conformity_level,
                                               response.more_follows, response.object_count},
                                              response.objects);
    }
    return detail::finish<Response>(in, response);
}

Result<Response> decode_exception(std::uint8_t code, FieldReader& in) {
    ExceptionResponse response;
    response.function = static_cast<std::uint8_t>(code & ~kExceptionBit);
    std::uint8_t exception = 0;
    in.u8(exception, "exception code").end();
    response.code = static_cast<ExceptionCode>(exception);
    return detail::finish<Response>(in, response);
}

struct ResponseDecoders : detail::SharedDecoders<Response, Direction::Response> {
    using Message = Response;
    using Raw = RawResponse;

    static Result<Response> read_bits(FunctionCode function, FieldReader& in) {
        ReadBitsResponse response;
        response.function = function;
        in.counted_rest(kPackedBitsCount, response.packed);
        return detail::finish<Response>(in, response);
    }
    static Result<Response> read_registers(FunctionCode function, FieldReader& in) {
        ReadRegistersResponse response;
        response.function = function;
        return decode_registers(in, response);
    }
    static Result<Response> read_exception_status(FieldReader& in) {
        ReadExceptionStatusResponse response;
        in.u8(response.status, "output data").end();
        return detail::finish<Response>(in, response);
    }
    static Result<Response> comm_event_counter(FieldReader& in) {
        GetCommEventCounterResponse response;
        in.u16(response.status, "status").u16(response.event_count, "event count").end();
        return detail::finish<Response>(in, response);
    }
    static Result<Response> comm_event_log(FieldReader& in) {
        GetCommEventLogResponse response;
        std::uint8_t byte_count = 0;
        in.u8(byte_count, "byte count")
            .require(byte_count >= kEventLogHeader &&
                         byte_count <= kEventLogHeader + limits::kMaxEventLogEvents,
                     value_error("byte count", "must be 6..70 (status, counts and 0..64 events)"))
            .counts_rest(byte_count, "byte count")
            .u16(response.status, "status")
            .u16(response.event_count, "event count")
            .u16(response.message_count, "message count")
            .rest(response.events);
        return detail::finish<Response>(in, response);
    }
    static Result<Response> write_multiple_coils(FieldReader& in) {
        return decode_write_multiple<WriteMultipleCoilsResponse>(in, detail::kWriteCoilsLimit);
    }
    static Result<Response> write_multiple_registers(FieldReader& in) {
        return decode_write_multiple<WriteMultipleRegistersResponse>(in,
                                                                     detail::kWriteRegistersLimit);
    }
    static Result<Response> report_server_id(FieldReader& in) {
        ReportServerIdResponse response;
        in.counted_rest(kServerIdCount, response.data);
        return detail::finish<Response>(in, response);
    }
    static Result<Response> read_file_record(FieldReader& in) {
        ReadFileRecordResponse response;
        detail::read_file_record_response_body(in, response.sub_responses);
        return detail::finish<Response>(in, response);
    }
    static Result<Response> read_write_multiple_registers(FieldReader& in) {
        return decode_registers(in, ReadWriteMultipleRegistersResponse{});
    }
    static Result<Response> read_fifo_queue(FieldReader& in) {
        ReadFifoQueueResponse response;
        std::uint16_t byte_count = 0;
        std::uint16_t fifo_count = 0;
        std::span<const std::uint8_t> values;
        in.u16(byte_count, "byte count")
            .counts_rest(byte_count, "byte count")
            .u16(fifo_count, "FIFO count")
            .require(fifo_count <= limits::kMaxFifoCount,
                     value_error("FIFO count", "must be 0..31"))
            .require(byte_count == 2 + 2 * std::size_t{fifo_count},
                     value_error("byte count", "must be 2 + 2 x FIFO count"))
            .rest(values);
        response.values = RegisterView(values);
        return detail::finish<Response>(in, response);
    }
    static Result<Response> encapsulated(FieldReader& in) {
        std::uint8_t mei_type = 0;
        in.u8(mei_type, "MEI type");
        if (in.ok() && mei_type == kMeiReadDeviceId) return decode_read_device_id(in);
        return canopen(in, mei_type, value_error("MEI type", "must be 0x0D or 0x0E"));
    }
    static Result<Response> object_messaging(FieldReader& in) {
        ObjectMessagingResponse response;
        detail::read_object_messaging_header(
            in, response, limits::kMinObjectMessagingResponseFragment,
            "must be 9 or more (protocol, class, instance, service code, error code, parameters)");
        in.u16(response.error_code, "service error code").rest(response.parameters);
        return detail::finish<Response>(in, response);
    }
};

Result<Response> decode_body(std::uint8_t code, FieldReader& in) {
    if (code & kExceptionBit) return decode_exception(code, in);
    return detail::decode_by_function<ResponseDecoders>(code, in);
}

}  // namespace

Result<Response> decode_response(std::span<const std::uint8_t> pdu) {
    return detail::decode_pdu<Response>(pdu, decode_body);
}

}  // namespace mblab::protocol
