#include <array>

#include "protocol/encode_support.hpp"
#include "protocol/limits.hpp"
#include "protocol/message_function.hpp"
#include "protocol/request.hpp"

namespace mblab::protocol {

namespace {

// Writes the fields after the function code. False when a length does not fit its count field.
struct RequestBodyWriter : detail::SharedBodyWriter {
    using SharedBodyWriter::operator();

    template <class Range>  // 01..04, and the head of 0F and 10
    bool range(const Range& r) const {
        return detail::put_words(out, r.address, r.quantity);
    }
    bool operator()(const ReadBitsRequest& r) const { return range(r); }
    bool operator()(const ReadRegistersRequest& r) const { return range(r); }
    template <FunctionCode Code>
    bool operator()(const CodeOnly<Code>&) const {
        return true;
    }
    template <FunctionCode Code, class Values>
    bool operator()(const WriteMultipleFields<Code, Values>& r) const {
        return range(r) && detail::put_counted(out, r.values.bytes());
    }
    bool operator()(const ReadFileRecordRequest& r) const {
        return detail::put_counted(out, r.sub_requests);
    }
    bool operator()(const ReadWriteMultipleRegistersRequest& r) const {
        detail::put_words(out, r.read_address, r.read_quantity, r.write_address, r.write_quantity);
        return detail::put_counted(out, r.values.bytes());
    }
    bool operator()(const ReadFifoQueueRequest& r) const {
        return detail::put_words(out, r.address);
    }
    bool operator()(const ReadDeviceIdRequest& r) const {
        out.put_u8(kMeiReadDeviceId);
        out.put_u8(r.read_code);
        out.put_u8(r.object_id);
        return true;
    }
    bool operator()(const ObjectMessagingRequest& r) const {
        return detail::put_object_messaging(out, r, limits::kMinObjectMessagingRequestFragment,
                                            r.parameters);
    }
};

}  // namespace

std::uint8_t function_of(const Request& request) {
    return std::visit([](const auto& message) { return detail::function_byte(message); }, request);
}

bool encode_request(const Request& request, WriteCursor& out) {
    out.put_u8(function_of(request));
    return std::visit(RequestBodyWriter{{out}}, request) && out.ok();
}

std::vector<std::uint8_t> encoded_pdu(const Request& request) {
    std::array<std::uint8_t, limits::kMaxPdu> buffer{};
    WriteCursor out(buffer);
    if (!encode_request(request, out) || !out.ok()) return {};
    const auto bytes = out.written();
    return {bytes.begin(), bytes.end()};
}

}  // namespace mblab::protocol
