#include "protocol/rtu_frame_length.hpp"

#include <array>

#include "protocol/function_code.hpp"
#include "protocol/function_table.hpp"
#include "protocol/limits.hpp"

namespace mblab::protocol {

namespace {

using Kind = RtuFrameLength::Kind;

// ADU offsets: the address comes first, so PDU offset n is ADU offset n + 1.
constexpr std::size_t kPdu = 1;
constexpr std::size_t kCrc = 2;

RtuFrameLength known(std::size_t pdu_size) {
    return {Kind::Known, kPdu + pdu_size + kCrc};
}
RtuFrameLength need(std::size_t bytes) {
    return {Kind::NeedBytes, bytes};
}
constexpr RtuFrameLength kUnknown{Kind::Unknown, 0};

// A PDU whose count field (1 or 2 bytes, big-endian) at PDU offset `at` gives the bytes after it.
RtuFrameLength counted(std::span<const std::uint8_t> head, std::size_t at, std::size_t width = 1) {
    const std::size_t field_end = kPdu + at + width;
    if (head.size() < field_end) return need(field_end);
    std::size_t count = 0;
    for (std::size_t i = kPdu + at; i < field_end; ++i)
        count = count << 8 | head[i];
    return known(at + width + count);
}

// Sub-function 00 echoes data of any length; other known sub-functions carry one data word.
// Sub-functions mblab does not know may carry anything.
RtuFrameLength diagnostics(std::span<const std::uint8_t> head) {
    constexpr std::size_t kSubEnd = kPdu + 3;
    if (head.size() < kSubEnd) return need(kSubEnd);
    const auto sub = static_cast<std::uint16_t>(head[kPdu + 1] << 8 | head[kPdu + 2]);
    if (sub == static_cast<std::uint16_t>(DiagnosticSub::ReturnQueryData) ||
        !is_known_diagnostic_sub(sub)) {
        return kUnknown;
    }
    return known(5);
}

// Only MEI 0x0E (read device identification) has a layout mblab knows.
bool is_read_device_id(std::span<const std::uint8_t> head) {
    return head[kPdu + 1] == kMeiReadDeviceId;
}

// The response lists its objects as (id, length, value); walking them finds the end.
RtuFrameLength device_id_response(std::span<const std::uint8_t> head) {
    constexpr std::size_t kMeiEnd = kPdu + 2;
    constexpr std::size_t kCountAt = kPdu + 6;
    if (head.size() < kMeiEnd) return need(kMeiEnd);
    if (!is_read_device_id(head)) return kUnknown;
    if (head.size() <= kCountAt) return need(kCountAt + 1);
    std::size_t end = kCountAt + 1;
    for (unsigned object = 0; object < head[kCountAt]; ++object) {
        // Past the limit the frame is malformed whatever follows; the framer reports it.
        if (end + kCrc > limits::kMaxRtuAdu) break;
        if (head.size() < end + 2) return need(end + 2);
        end += 2 + head[end + 1];
    }
    return {Kind::Known, end + kCrc};
}

RtuFrameLength device_id_request(std::span<const std::uint8_t> head) {
    constexpr std::size_t kMeiEnd = kPdu + 2;
    if (head.size() < kMeiEnd) return need(kMeiEnd);
    return is_read_device_id(head) ? known(4) : kUnknown;
}

// Dense copies of the table's layout columns, indexed by function code: one load per byte fed.
// Codes without a row stay Unknown.
struct LayoutIndex {
    std::array<PduLayout, 256> request{};
    std::array<PduLayout, 256> response{};
};

constexpr LayoutIndex make_index() {
    LayoutIndex index;
    for (const FunctionRow& row : kFunctionTable) {
        index.request[static_cast<std::uint8_t>(row.code)] = row.request;
        index.response[static_cast<std::uint8_t>(row.code)] = row.response;
    }
    return index;
}

constexpr LayoutIndex kIndex = make_index();

RtuFrameLength measure(PduLayout layout, std::span<const std::uint8_t> head) {
    switch (layout.shape) {
        case PduShape::Unknown:
            return kUnknown;
        case PduShape::Fixed:
            return known(layout.value);
        case PduShape::Count8:
            return counted(head, layout.value);
        case PduShape::Count16:
            return counted(head, layout.value, 2);
        case PduShape::Diagnostics:
            return diagnostics(head);
        case PduShape::DeviceIdRequest:
            return device_id_request(head);
        case PduShape::DeviceIdResponse:
            return device_id_response(head);
    }
    return kUnknown;
}

}  // namespace

RtuFrameLength rtu_frame_length(Direction direction, std::span<const std::uint8_t> head) {
    constexpr std::size_t kFunctionEnd = kPdu + 1;
    if (head.size() < kFunctionEnd) return need(kFunctionEnd);
    const std::uint8_t code = head[kPdu];
    if (direction == Direction::Request) return measure(kIndex.request[code], head);
    // An exception response is the function code with its high bit set, then the exception code.
    if (code & kExceptionBit) return known(2);
    return measure(kIndex.response[code], head);
}

}  // namespace mblab::protocol
