#include "protocol/mbap_framer.hpp"

#include <algorithm>
#include <cstring>

namespace mblab::protocol {

namespace {

constexpr std::size_t kHeader = limits::kMbapHeader;
constexpr unsigned kMinLength = 2;                    // unit id + function code
constexpr unsigned kMaxLength = limits::kMaxPdu + 1;  // unit id + 253-byte PDU

// The length field counts from the unit id, the header's last byte.
std::size_t adu_size(const MbapHeader& header) {
    return kHeader - 1 + header.length;
}

}  // namespace

std::optional<Adu> MbapFramer::partial_frame() const {
    if (held_ < kHeader) return std::nullopt;
    return Adu{to_adu_header(read_mbap_header(buffer_)),
               {buffer_.data() + kHeader, held_ - kHeader}};
}

std::optional<FrameEvent> MbapFramer::check_length(const MbapHeader& header) {
    FrameEvent event;
    if (header.length < (lenient_ ? 1U : kMinLength)) {
        event = frame_error(error_.format("MBAP length %u is under %u (unit id and function code)",
                                          unsigned{header.length}, kMinLength));
    } else if (header.length > kMaxLength) {
        event = frame_error(error_.format("MBAP length %u exceeds %u (ADU over %zu bytes)",
                                          unsigned{header.length}, kMaxLength, limits::kMaxTcpAdu));
    } else {
        return std::nullopt;
    }
    event.header = to_adu_header(header);
    return event;
}

FrameEvent MbapFramer::finish(std::span<const std::uint8_t> adu) {
    FrameEvent event;
    event.header = to_adu_header(read_mbap_header(adu));
    event.adu = adu;
    event.pdu = adu.subspan(kHeader);
    if (event.header.protocol_id == kModbusProtocolId && event.header.length >= kMinLength) {
        event.status = FrameStatus::Frame;
    } else if (lenient_) {
        event.status = FrameStatus::Frame;
        event.violation =
            event.header.protocol_id != kModbusProtocolId
                ? error_.format("MBAP protocol id 0x%04X is not 0 (Modbus)",
                                unsigned{event.header.protocol_id})
                : error_.format("MBAP length %u is under %u (unit id and function code)",
                                unsigned{event.header.length}, kMinLength);
    } else {
        event.status = FrameStatus::Error;
        event.error =
            error_.format("MBAP protocol id 0x%04X is not 0 (Modbus); %zu-byte frame skipped",
                          unsigned{event.header.protocol_id}, adu.size());
    }
    return event;
}

FrameEvent MbapFramer::feed(std::span<const std::uint8_t> input, std::size_t& consumed) {
    consumed = 0;
    if (held_ == 0 && input.size() >= kHeader) {
        const MbapHeader header = read_mbap_header(input);
        if (auto bad = check_length(header)) {
            consumed = kHeader;
            return *bad;
        }
        const std::size_t size = adu_size(header);
        if (input.size() >= size) {
            consumed = size;
            return finish(input.first(size));
        }
    }
    for (;;) {
        const bool in_header = held_ < kHeader;
        const std::size_t need = in_header ? kHeader : adu_size(read_mbap_header(buffer_));
        const std::size_t take = std::min(need - held_, input.size() - consumed);
        if (take > 0) std::memcpy(buffer_.data() + held_, input.data() + consumed, take);
        held_ += take;
        consumed += take;
        if (held_ < need) return FrameEvent{};
        if (in_header) {
            if (auto bad = check_length(read_mbap_header(buffer_))) {
                held_ = 0;
                return *bad;
            }
            continue;
        }
        held_ = 0;
        return finish({buffer_.data(), need});
    }
}

namespace {

// Whether `bytes` read as whole frames to the end, the last one possibly unfinished; at least
// one must be whole, so that a stray byte run is not taken for a request.
bool frames_to_end(std::span<const std::uint8_t> bytes) {
    std::size_t whole = 0;
    while (!bytes.empty()) {
        if (bytes.size() < kHeader) {
            // The start of a header: the protocol id bytes that came must be 0.
            const auto id = bytes.subspan(std::min<std::size_t>(2, bytes.size()));
            return whole > 0 &&
                   std::all_of(id.begin(), id.begin() + std::min<std::size_t>(2, id.size()),
                               [](std::uint8_t b) { return b == 0; });
        }
        const auto header = read_mbap_header(bytes);
        if (header.protocol_id != kModbusProtocolId || header.length < kMinLength ||
            header.length > kMaxLength) {
            return false;
        }
        const auto size = adu_size(header);
        if (bytes.size() < size) return whole > 0;
        bytes = bytes.subspan(size);
        ++whole;
    }
    return whole > 0;
}

}  // namespace

std::size_t mbap_resync_offset(std::span<const std::uint8_t> bytes) {
    for (std::size_t offset = 0; offset + kHeader < bytes.size(); ++offset) {
        if (frames_to_end(bytes.subspan(offset))) return offset;
    }
    return bytes.size();
}

}  // namespace mblab::protocol
