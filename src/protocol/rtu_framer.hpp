#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/frame_error_text.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/limits.hpp"
#include "protocol/rtu_frame_length.hpp"

namespace mblab::protocol {

// Splits a Modbus RTU byte stream into frames. The end of a frame is found two ways:
// - from the function code's layout (rtu_frame_length), which separates back-to-back frames and
//   answers without waiting for t3.5;
// - from silence: the caller, which owns the clock, calls on_silence() after t3.5 without bytes
//   (or a gap over t1.5 inside a frame). Silence is authoritative: whatever is held then is the
//   whole frame and its CRC decides, so a truncated but CRC-correct frame is reported as a Frame
//   (the PDU decoder then rejects it), and a frame whose layout claimed more bytes than arrived
//   is an Error.
//
// After an Error the bad frame's bytes are dropped and the next byte is taken as the start of a
// new frame. When a corrupted length field put the framer out of step, the next silence puts it
// back: silence always ends whatever is held, so the frame after it is never lost.
//
// A layout announcing more than 256 bytes (a byte count beyond the frame) is treated as one that
// gives no length: silence, or a CRC match on links without silence, ends the frame.
//
// Errors: CRC mismatch; more than 256 bytes without an end; a frame under 4 bytes at silence; an
// incomplete frame at silence.
class RtuFramer {
  public:
    // What ends a frame whose layout does not give its length (unknown function codes, FC 08
    // sub-function 00, ...).
    enum class UnknownLength : std::uint8_t {
        AwaitSilence,  // only on_silence(): right for serial lines
        // Also the first point where the CRC matches (at least 4 bytes). For links without
        // silence (RTU over TCP); it may cut a frame early once in 65536 positions.
        EndOnCrcMatch,
    };

    // Lenient (the tester's mode): a frame whose CRC does not match comes through as a Frame
    // with `violation` set, since its extent is known and its bytes are worth showing.
    explicit RtuFramer(Direction direction,
                       UnknownLength unknown_length = UnknownLength::AwaitSilence,
                       bool lenient = false)
        : direction_(direction), unknown_length_(unknown_length), lenient_(lenient) {}

    // Same contract as MbapFramer::feed: the first event, `consumed` bytes used; NeedMore means
    // all of `input` was consumed; every Frame or Error consumes at least one byte.
    FrameEvent feed(std::span<const std::uint8_t> input, std::size_t& consumed);
    // The caller saw t3.5 of silence: the held bytes end a frame (CRC checked) or are dropped.
    // NeedMore when nothing was held.
    FrameEvent on_silence();

    bool has_partial() const { return held_ > 0; }
    void reset();
    Direction direction() const { return direction_; }

  private:
    std::span<const std::uint8_t> held() const { return {buffer_.data(), held_}; }
    FrameEvent check_crc(std::span<const std::uint8_t> adu);
    FrameEvent drop(FrameEvent event);
    bool crc_matches_held();

    Direction direction_;
    UnknownLength unknown_length_;
    bool lenient_ = false;
    std::array<std::uint8_t, limits::kMaxRtuAdu> buffer_{};
    std::size_t held_ = 0;
    // Running CRC over buffer_[0, crc_len_) for EndOnCrcMatch.
    std::uint16_t crc_ = 0xFFFF;
    std::size_t crc_len_ = 0;
    FrameErrorText error_;
};

}  // namespace mblab::protocol
