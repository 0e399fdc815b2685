#include "protocol/file_record.hpp"
#include "protocol/function_dispatch.hpp"
#include "protocol/limits.hpp"
#include "protocol/message_checks.hpp"
#include "protocol/request.hpp"

// Each decoder reads the fields of [APP]'s request table, then checks in the order of its state
// diagram: every exception 03 check (lengths, quantities, values) before any 02 check (address
// ranges), so a request that is wrong in both ways gets 03, as a server following [APP] answers.
namespace mblab::protocol {

namespace {

using detail::FieldReader;
using detail::value_error;

// 0F and 10: starting address, quantity, byte count, then the values the byte count counts.
struct MultipleWriteLayout {
    detail::QuantityLimit limit;
    std::size_t (*bytes_for)(std::size_t quantity);
    const char* byte_count_reason;
    const char* values_field;
};

std::size_t two_bytes_each(std::size_t quantity) {
    return 2 * quantity;
}

constexpr MultipleWriteLayout kWriteCoilsLayout{detail::kWriteCoilsLimit, detail::packed_size,
                                                "must be quantity / 8 rounded up", "outputs value"};
constexpr MultipleWriteLayout kWriteRegistersLayout{detail::kWriteRegistersLimit, two_bytes_each,
                                                    "must be 2 x quantity", "registers value"};

template <class Message>
std::span<const std::uint8_t> read_multiple_write(FieldReader& in, Message& request,
                                                  const MultipleWriteLayout& layout) {
    std::uint8_t byte_count = 0;
    std::span<const std::uint8_t> values;
    in.u16(request.address, "starting address")
        .u16(request.quantity, "quantity")
        .u8(byte_count, "byte count");
    detail::check_quantity(in, request.quantity, layout.limit);
    in.require(byte_count == layout.bytes_for(request.quantity),
               value_error("byte count", layout.byte_count_reason))
        .counts_rest(byte_count, "byte count")
        .bytes(byte_count, values, layout.values_field);
    detail::check_address_span(in, request.address, request.quantity, "starting address");
    return values;
}

// 01..04: starting address and quantity.
template <class Message>
Result<Request> decode_read_range(FunctionCode function, FieldReader& in,
                                  const detail::QuantityLimit& limit) {
    Message request;
    request.function = function;
    in.u16(request.address, "starting address").u16(request.quantity, "quantity").end();
    detail::check_quantity(in, request.quantity, limit);
    detail::check_address_span(in, request.address, request.quantity, "starting address");
    return detail::finish<Request>(in, request);
}

// 07, 0B, 0C, 11: the function code is the whole request.
template <class Message>
Result<Request> decode_bare(FieldReader& in) {
    in.end();
    return detail::finish<Request>(in, Message{});
}

struct RequestDecoders : detail::SharedDecoders<Request, Direction::Request> {
    using Message = Request;
    using Raw = RawRequest;

    static Result<Request> read_bits(FunctionCode function, FieldReader& in) {
        return decode_read_range<ReadBitsRequest>(function, in, detail::kReadBitsLimit);
    }
    static Result<Request> read_registers(FunctionCode function, FieldReader& in) {
        return decode_read_range<ReadRegistersRequest>(function, in, detail::kReadRegistersLimit);
    }
    static Result<Request> read_exception_status(FieldReader& in) {
        return decode_bare<ReadExceptionStatusRequest>(in);
    }
    static Result<Request> comm_event_counter(FieldReader& in) {
        return decode_bare<GetCommEventCounterRequest>(in);
    }
    static Result<Request> comm_event_log(FieldReader& in) {
        return decode_bare<GetCommEventLogRequest>(in);
    }
    static Result<Request> write_multiple_coils(FieldReader& in) {
        WriteMultipleCoilsRequest request;
        const auto packed = read_multiple_write(in, request, kWriteCoilsLayout);
        request.values = BitView(packed, request.quantity);
        return detail::finish<Request>(in, request);
    }
    static Result<Request> write_multiple_registers(FieldReader& in) {
        WriteMultipleRegistersRequest request;
        request.values = RegisterView(read_multiple_write(in, request, kWriteRegistersLayout));
        return detail::finish<Request>(in, request);
    }
    static Result<Request> report_server_id(FieldReader& in) {
        return decode_bare<ReportServerIdRequest>(in);
    }
    static Result<Request> read_file_record(FieldReader& in) {
        ReadFileRecordRequest request;
        detail::read_file_record_request_body(in, request.sub_requests);
        return detail::finish<Request>(in, request);
    }
    static Result<Request> read_write_multiple_registers(FieldReader& in) {
        ReadWriteMultipleRegistersRequest request;
        std::uint8_t byte_count = 0;
        std::span<const std::uint8_t> values;
        in.u16(request.read_address, "read starting address")
            .u16(request.read_quantity, "quantity to read")
            .u16(request.write_address, "write starting address")
            .u16(request.write_quantity, "quantity to write")
            .u8(byte_count, "write byte count");
        detail::check_quantity(in, request.read_quantity, detail::kReadWriteReadLimit);
        detail::check_quantity(in, request.write_quantity, detail::kReadWriteWriteLimit);
        in.require(byte_count == 2 * request.write_quantity,
                   value_error("write byte count", "must be 2 x quantity to write"))
            .counts_rest(byte_count, "write byte count")
            .bytes(byte_count, values, "write registers value");
        // Both ranges: checking only the read range let CVE-2022-0367 write out of bounds.
        detail::check_address_span(in, request.read_address, request.read_quantity,
                                   "read starting address");
        detail::check_address_span(in, request.write_address, request.write_quantity,
                                   "write starting address");
        request.values = RegisterView(values);
        return detail::finish<Request>(in, request);
    }
    static Result<Request> read_fifo_queue(FieldReader& in) {
        ReadFifoQueueRequest request;
        in.u16(request.address, "FIFO pointer address").end();
        return detail::finish<Request>(in, request);
    }
    static Result<Request> encapsulated(FieldReader& in) {
        std::uint8_t mei_type = 0;
        in.u8(mei_type, "MEI type");
        if (in.ok() && mei_type == kMeiReadDeviceId) {
            ReadDeviceIdRequest request;
            in.u8(request.read_code, "read device id code")
                .u8(request.object_id, "object id")
                .end();
            detail::check_read_device_id_code(in, request.read_code);
            return detail::finish<Request>(in, request);
        }
        // Other MEI types are reserved ([APP] annex A): the function is not supported.
        return canopen(in, mei_type, detail::function_error("MEI type", "must be 0x0D or 0x0E"));
    }
    static Result<Request> object_messaging(FieldReader& in) {
        ObjectMessagingRequest request;
        detail::read_object_messaging_header(
            in, request, limits::kMinObjectMessagingRequestFragment,
            "must be 7 or more (protocol, class, instance, service code, parameters)");
        in.rest(request.parameters);
        return detail::finish<Request>(in, request);
    }
};

}  // namespace

Result<Request> decode_request(std::span<const std::uint8_t> pdu) {
    return detail::decode_pdu<Request>(pdu, detail::decode_by_function<RequestDecoders>);
}

}  // namespace mblab::protocol
