#include "protocol/ascii_framer.hpp"

#include "protocol/lrc.hpp"
#include "support/hex_digits.hpp"

namespace mblab::protocol {

namespace {

constexpr std::size_t kMinBytes = 3;  // address, function code, LRC

bool lower_case_hex(std::uint8_t c) {
    return c >= 'a' && c <= 'f';
}

}  // namespace

void AsciiFramer::start_frame() {
    state_ = State::Body;
    chars_[0] = ':';
    char_count_ = 1;
    byte_count_ = 0;
    high_nibble_ = -1;
    lower_case_at_ = 0;
}

FrameEvent AsciiFramer::fail(FrameEvent event) {
    state_ = State::Hunting;
    return event;
}

FrameEvent AsciiFramer::feed(std::span<const std::uint8_t> input, std::size_t& consumed) {
    consumed = 0;
    FrameEvent event;
    while (consumed < input.size()) {
        if (step(input[consumed++], event)) return event;
    }
    return FrameEvent{};
}

FrameEvent AsciiFramer::on_silence() {
    if (state_ == State::Hunting) return FrameEvent{};
    // A frame that stops after its CR lacks the end delimiter [SER 2.5.2.1]: say so.
    if (state_ == State::AfterCr) {
        return fail(frame_error(
            error_.format("incomplete frame: CR not followed by 0x%02X (LF) after %zu characters",
                          unsigned{end_}, char_count_)));
    }
    return fail(
        frame_error(error_.format("incomplete frame: timeout after %zu characters", char_count_)));
}

bool AsciiFramer::step(std::uint8_t c, FrameEvent& event) {
    // ':' begins a frame wherever it appears [SER 2.5.2.1]; a frame it interrupts is lost.
    if (c == ':') {
        const bool interrupted = state_ != State::Hunting;
        const std::size_t dropped = char_count_;
        start_frame();
        if (!interrupted) return false;
        event =
            frame_error(error_.format("frame interrupted by ':' after %zu characters", dropped));
        return true;
    }
    if (state_ == State::Hunting) return false;
    return frame_char(c, event);
}

bool AsciiFramer::frame_char(std::uint8_t c, FrameEvent& event) {
    if (char_count_ == chars_.size()) {
        event = fail(frame_error(error_.format("frame over %zu characters", chars_.size())));
        return true;
    }
    chars_[char_count_++] = c;
    if (state_ == State::AfterCr) {
        if (c == end_) {
            event = finish();
            return true;
        }
        event = fail(frame_error(
            error_.format("CR followed by 0x%02X instead of 0x%02X", unsigned{c}, unsigned{end_})));
        return true;
    }
    if (c == '\r') {
        state_ = State::AfterCr;
        return false;
    }
    return hex_digit(c, event);
}

bool AsciiFramer::hex_digit(std::uint8_t c, FrameEvent& event) {
    int value = upper_hex_value(static_cast<char>(c));
    // [SER 2.5.2]: the hex digits of a frame are 0-9 and A-F; a lower-case digit is a framing
    // error a strict reader drops the frame for, which the tester names rather than decodes.
    if (value < 0 && lower_case_hex(c)) {
        if (!lenient_) {
            event = fail(frame_error(error_.format(
                "lower-case hex digit '%c' at position %zu (only 0-9 and A-F are allowed)", c,
                char_count_ - 1)));
            return true;
        }
        if (lower_case_at_ == 0) lower_case_at_ = char_count_ - 1;
        value = c - 'a' + 10;
    }
    if (value < 0) {
        event = fail(frame_error(error_.format("non-hex character 0x%02X at position %zu",
                                               unsigned{c}, char_count_ - 1)));
        return true;
    }
    if (high_nibble_ < 0) {
        high_nibble_ = value;
        return false;
    }
    bytes_[byte_count_++] = static_cast<std::uint8_t>(high_nibble_ << 4 | value);
    high_nibble_ = -1;
    return false;
}

FrameEvent AsciiFramer::finish() {
    state_ = State::Hunting;
    const std::span<const std::uint8_t> chars(chars_.data(), char_count_);
    const std::size_t digits = char_count_ - 3;  // without ':', CR and the end delimiter
    FrameEvent event;
    if (high_nibble_ >= 0) {
        event = frame_error(error_.format("odd number of hex digits (%zu)", digits));
    } else if (byte_count_ < kMinBytes) {
        event = frame_error(
            error_.format("frame under %zu bytes (%zu decoded)", kMinBytes, byte_count_));
    } else {
        const std::size_t body = byte_count_ - 1;
        const std::uint8_t computed = lrc({bytes_.data(), body});
        const auto pdu = std::span<const std::uint8_t>(bytes_).subspan(1, body - 1);
        if (computed != bytes_[body]) {
            const char* why = error_.format("LRC mismatch: frame has 0x%02X, computed 0x%02X",
                                            unsigned{bytes_[body]}, unsigned{computed});
            if (lenient_) {
                event.status = FrameStatus::Frame;
                event.violation = why;
            } else {
                event = frame_error(why);
            }
        } else if (lower_case_at_ != 0) {
            event.status = FrameStatus::Frame;
            event.violation =
                error_.format("lower-case hex digit at position %zu (only 0-9 and A-F are allowed)",
                              lower_case_at_);
        } else {
            event.status = FrameStatus::Frame;
        }
        if (event.is_frame()) event.pdu = pdu;
        event.header = {Framing::Ascii, bytes_[0]};
    }
    event.adu = chars;
    return event;
}

}  // namespace mblab::protocol
