#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/frame_error_text.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/limits.hpp"

namespace mblab::protocol {

// Splits a Modbus ASCII character stream into frames: ':' then hex of address, PDU and LRC, then
// CR LF [SER 2.5.2]. Hex digits are upper case: a lower-case one is a framing error (lenient: a
// violation of a frame otherwise read). Characters outside a frame are
// skipped; ':' always starts a new frame, so after any error the next good frame is found.
//
// The event's adu is the frame's characters (':' .. LF); pdu and unit are decoded from the hex.
//
// Errors: a character that is not hex (the rest of that frame is skipped up to the next ':'),
// CR not followed by LF, ':' inside a frame (the old frame is dropped, the new one kept), odd
// number of hex digits, fewer than 3 bytes, bad LRC, more than 513 characters.
class AsciiFramer {
  public:
    // Lenient (the tester's mode): a frame whose LRC does not match comes through as a Frame with
    // `violation` set.
    explicit AsciiFramer(bool lenient = false) : lenient_(lenient) {}

    // Same contract as MbapFramer::feed: the first event, `consumed` bytes used; NeedMore means
    // all of `input` was consumed; every Frame or Error consumes at least one byte.
    FrameEvent feed(std::span<const std::uint8_t> input, std::size_t& consumed);
    // The inter-character timeout (1 s by default) expired: an unfinished frame is dropped and
    // reported as Error; NeedMore when nothing was held.
    FrameEvent on_silence();

    bool has_partial() const { return state_ != State::Hunting; }
    void reset() { state_ = State::Hunting; }
    // The character after CR that ends a frame: LF unless changed by FC 08 sub-function 03.
    void set_end_delimiter(std::uint8_t end) { end_ = end; }
    std::uint8_t end_delimiter() const { return end_; }

  private:
    enum class State : std::uint8_t { Hunting, Body, AfterCr };

    void start_frame();
    // Each handles one character and returns true with `event` set when it produced an event.
    bool step(std::uint8_t c, FrameEvent& event);
    bool frame_char(std::uint8_t c, FrameEvent& event);
    bool hex_digit(std::uint8_t c, FrameEvent& event);
    FrameEvent finish();
    FrameEvent fail(FrameEvent event);

    State state_ = State::Hunting;
    std::uint8_t end_ = '\n';
    std::array<std::uint8_t, limits::kMaxAsciiChars> chars_{};
    std::size_t char_count_ = 0;
    // Decoded bytes: address, PDU, LRC; sized for every hex digit a 513-character frame holds.
    std::array<std::uint8_t, (limits::kMaxAsciiChars - 1) / 2> bytes_{};
    std::size_t byte_count_ = 0;
    int high_nibble_ = -1;
    std::size_t lower_case_at_ = 0;  // position of the first lower-case digit (lenient); 0: none
    bool lenient_ = false;
    FrameErrorText error_;
};

}  // namespace mblab::protocol
