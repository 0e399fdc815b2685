#pragma once

#include <cstdint>
#include <span>

#include "protocol/adu.hpp"

namespace mblab::protocol {

enum class FrameStatus : std::uint8_t { NeedMore, Frame, Error };

// What a framer reports after a feed(): nothing yet, a whole frame, or a frame it dropped.
// The spans point into the caller's input or into the framer's own buffer; either way they stay
// valid until the next call on that framer (feed, on_silence, reset) and while the input is
// unchanged.
struct FrameEvent {
    FrameStatus status = FrameStatus::NeedMore;
    // The whole frame as received: MBAP header .. PDU end; RTU address .. CRC; ASCII ':' .. LF.
    // Errors about a whole received frame (bad CRC, LRC, protocol id) set it too, for logging.
    std::span<const std::uint8_t> adu;
    // The PDU inside it, function code first (for ASCII: decoded from hex).
    std::span<const std::uint8_t> pdu;
    // Framing, unit and, for MBAP, the header's fields as received (length included): set for
    // frames and for errors about a received header or frame.
    AduHeader header{};
    // When status == Error: why, e.g. "MBAP length 300 exceeds 254". Owned by the framer.
    const char* error = "";
    // Lenient framers only: why a strict framer would have refused this Frame (a protocol id
    // other than 0, a bad checksum); empty when it is clean.
    const char* violation = "";

    bool is_frame() const { return status == FrameStatus::Frame; }
    bool is_error() const { return status == FrameStatus::Error; }
    bool is_clean_frame() const { return is_frame() && *violation == '\0'; }
};

inline FrameEvent frame_error(const char* reason) {
    FrameEvent event;
    event.status = FrameStatus::Error;
    event.error = reason;
    return event;
}

}  // namespace mblab::protocol
