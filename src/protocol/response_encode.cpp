#include "protocol/encode_support.hpp"
#include "protocol/limits.hpp"
#include "protocol/message_function.hpp"
#include "protocol/response.hpp"

namespace mblab::protocol {

namespace {

constexpr std::size_t kEventLogHeader = 6;  // status, event count, message count

// Writes the fields after the function code. False when a length does not fit its count field.
struct ResponseBodyWriter : detail::SharedBodyWriter {
    using SharedBodyWriter::operator();

    bool operator()(const ReadBitsResponse& r) const { return detail::put_counted(out, r.packed); }
    bool operator()(const ReadRegistersResponse& r) const {
        return detail::put_counted(out, r.values.bytes());
    }
    bool operator()(const ReadExceptionStatusResponse& r) const {
        out.put_u8(r.status);
        return true;
    }
    bool operator()(const GetCommEventCounterResponse& r) const {
        return detail::put_words(out, r.status, r.event_count);
    }
    bool operator()(const GetCommEventLogResponse& r) const {
        const std::size_t byte_count = kEventLogHeader + r.events.size();
        if (byte_count > 0xFF) return false;
        out.put_u8(static_cast<std::uint8_t>(byte_count));
        detail::put_words(out, r.status, r.event_count, r.message_count);
        out.put_bytes(r.events);
        return true;
    }
    template <FunctionCode Code>
    bool operator()(const AddressQuantity<Code>& r) const {
        return detail::put_words(out, r.address, r.quantity);
    }
    bool operator()(const ReportServerIdResponse& r) const {
        return detail::put_counted(out, r.data);
    }
    bool operator()(const ReadFileRecordResponse& r) const {
        return detail::put_counted(out, r.sub_responses);
    }
    bool operator()(const ReadWriteMultipleRegistersResponse& r) const {
        return detail::put_counted(out, r.values.bytes());
    }
    bool operator()(const ReadFifoQueueResponse& r) const {
        // The byte count covers the FIFO count and the values.
        const std::size_t byte_count = 2 + r.values.bytes().size();
        if (byte_count > 0xFFFF) return false;
        detail::put_words(out, byte_count, r.values.size());
        out.put_bytes(r.values.bytes());
        return true;
    }
    bool operator()(const ReadDeviceIdResponse& r) const {
        out.put_u8(kMeiReadDeviceId);
        out.put_u8(r.read_code);
        out.put_u8(r.conformity_level);
        out.put_u8(r.more_follows);
        out.put_u8(r.next_object_id);
        out.put_u8(r.object_count);
        out.put_bytes(r.objects);
        return true;
    }
    bool operator()(const ObjectMessagingResponse& r) const {
        return detail::put_object_messaging(out, r, limits::kMinObjectMessagingResponseFragment,
                                            r.parameters, r.error_code);
    }
    bool operator()(const ExceptionResponse& r) const {
        out.put_u8(static_cast<std::uint8_t>(r.code));
        return true;
    }
};

}  // namespace

std::uint8_t function_of(const Response& response) {
    if (const auto* exception = std::get_if<ExceptionResponse>(&response)) {
        return static_cast<std::uint8_t>(exception->function | kExceptionBit);
    }
    return std::visit([](const auto& message) { return detail::function_byte(message); }, response);
}

bool encode_response(const Response& response, WriteCursor& out) {
    out.put_u8(function_of(response));
    return std::visit(ResponseBodyWriter{{out}}, response) && out.ok();
}

bool encode_exception(std::uint8_t function, ExceptionCode code, WriteCursor& out) {
    ExceptionResponse exception;
    exception.function = function;
    exception.code = code;
    return encode_response(exception, out);
}

}  // namespace mblab::protocol
