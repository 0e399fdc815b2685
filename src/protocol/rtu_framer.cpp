#include "protocol/rtu_framer.hpp"

#include <algorithm>
#include <cstring>

#include "protocol/crc16.hpp"

namespace mblab::protocol {

namespace {

using Kind = RtuFrameLength::Kind;
constexpr std::size_t kMinFrame = 4;  // address, function code, CRC
constexpr std::size_t kMaxFrame = limits::kMaxRtuAdu;

}  // namespace

void RtuFramer::reset() {
    held_ = 0;
    crc_ = kCrc16Initial;
    crc_len_ = 0;
}

FrameEvent RtuFramer::drop(FrameEvent event) {
    reset();
    return event;
}

FrameEvent RtuFramer::check_crc(std::span<const std::uint8_t> adu) {
    const std::size_t body = adu.size() - 2;
    const std::uint16_t computed = crc16(adu.first(body));
    const auto received = static_cast<std::uint16_t>(adu[body] | adu[body + 1] << 8);
    FrameEvent event;
    event.adu = adu;
    event.header = {Framing::Rtu, adu[0]};
    event.status = FrameStatus::Frame;
    event.pdu = adu.subspan(1, body - 1);
    if (computed != received) {
        const char* why = error_.format("CRC mismatch: frame has 0x%04X, computed 0x%04X",
                                        unsigned{received}, unsigned{computed});
        if (lenient_) {
            event.violation = why;
        } else {
            event.status = FrameStatus::Error;
            event.error = why;
            event.pdu = {};
        }
    }
    return event;
}

bool RtuFramer::crc_matches_held() {
    for (; crc_len_ < held_; ++crc_len_)
        crc_ = crc16_update(crc_, buffer_[crc_len_]);
    return crc_ == 0;  // the CRC over a frame including its own CRC bytes is 0
}

FrameEvent RtuFramer::feed(std::span<const std::uint8_t> input, std::size_t& consumed) {
    consumed = 0;
    if (held_ == 0) {
        const RtuFrameLength length = rtu_frame_length(direction_, input);
        if (length.kind == Kind::Known && length.bytes <= kMaxFrame &&
            length.bytes <= input.size()) {
            consumed = length.bytes;
            return check_crc(input.first(length.bytes));
        }
    }
    for (;;) {
        const RtuFrameLength length = rtu_frame_length(direction_, held());
        std::size_t want = 0;
        // A layout announcing more than an RTU frame holds (a byte count that lies) gives no end:
        // silence does, and the PDU decoder then answers the lie with exception 03.
        if (length.kind == Kind::Unknown || length.bytes > kMaxFrame) {
            const bool by_crc = unknown_length_ == UnknownLength::EndOnCrcMatch;
            if (by_crc && held_ >= kMinFrame && crc_matches_held()) return drop(check_crc(held()));
            if (held_ == kMaxFrame && consumed < input.size()) {
                ++consumed;  // the byte that made it too long goes with it
                return drop(frame_error(error_.format("no frame end within %zu bytes", kMaxFrame)));
            }
            // Matching the CRC needs a look after every byte.
            want = by_crc ? 1 : kMaxFrame - held_;
        } else if (length.kind == Kind::Known && held_ == length.bytes) {
            return drop(check_crc(held()));
        } else {
            want = length.bytes - held_;
        }
        want = std::min(want, input.size() - consumed);
        if (want == 0) return FrameEvent{};
        std::memcpy(buffer_.data() + held_, input.data() + consumed, want);
        held_ += want;
        consumed += want;
    }
}

FrameEvent RtuFramer::on_silence() {
    if (held_ == 0) return FrameEvent{};
    if (held_ < kMinFrame) {
        return drop(frame_error(
            error_.format("frame under %zu bytes (%zu before silence)", kMinFrame, held_)));
    }
    FrameEvent event = check_crc(held());
    const RtuFrameLength length = rtu_frame_length(direction_, held());
    if (event.is_error() && length.kind != Kind::Unknown && length.bytes > held_) {
        event.error =
            error_.format("incomplete frame: silence after %zu bytes, layout needs %s%zu", held_,
                          length.kind == Kind::NeedBytes ? "at least " : "", length.bytes);
    }
    return drop(event);
}

}  // namespace mblab::protocol
