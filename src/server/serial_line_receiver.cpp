#include "server/serial_line_receiver.hpp"

namespace mblab::server {

namespace {

constexpr std::size_t kMinRtuFrame = 4;  // address, function code, CRC

}  // namespace

SerialLineReceiver::SerialLineReceiver(LineFraming framing, LineTiming timing,
                                       protocol::Direction direction,
                                       protocol::RtuFramer::UnknownLength unknown_length)
    : framer_({.framing = framing, .direction = direction, .unknown_length = unknown_length}),
      timing_(timing) {}

bool SerialLineReceiver::has_partial() const {
    return framer_.has_partial();
}

LineClock::time_point SerialLineReceiver::deadline() const {
    // An RTU burst ends with silence even when the framer holds nothing: the silence closes
    // the burst's error count, and a frame of unknown length has no other end.
    const bool waiting = is_rtu() ? in_burst_ : has_partial();
    return waiting ? last_byte_ + timing_.silence : LineClock::time_point::max();
}

void SerialLineReceiver::receive(std::span<const std::uint8_t> bytes, LineClock::time_point now) {
    if (bytes.empty()) return;
    if (now >= deadline()) {
        silence_due_ = true;
    } else if (timing_.char_gap.count() > 0 && has_partial() && is_rtu() &&
               now - last_byte_ > timing_.char_gap) {
        broken_ = true;
    }
    input_ = bytes;
    position_ = 0;
    last_byte_ = now;
}

LineEvent SerialLineReceiver::next() {
    if (silence_due_) {
        silence_due_ = false;
        LineEvent event = silence();
        in_burst_ = true;  // the bytes waiting in input_ start the next burst
        if (!event.empty()) return event;
    }
    while (position_ < input_.size()) {
        in_burst_ = true;
        std::size_t consumed = 0;
        const auto rest = input_.subspan(position_);
        const protocol::FrameEvent event = framer_.feed(rest, consumed);
        position_ += consumed;
        if (event.status == protocol::FrameStatus::NeedMore) {
            held_ += consumed;
            continue;
        }
        const std::size_t held_before = held_;
        held_ = 0;
        return classify(event, held_before);
    }
    input_ = {};
    position_ = 0;
    return {};
}

LineEvent SerialLineReceiver::on_timeout(LineClock::time_point now) {
    if (now < deadline()) return {};
    return silence();
}

LineEvent SerialLineReceiver::silence() {
    const std::size_t held_before = held_;
    held_ = 0;
    in_burst_ = false;
    const protocol::FrameEvent event = framer_.on_silence();
    LineEvent out = classify(event, held_before);
    broken_ = false;
    error_counted_ = false;
    return out;
}

LineEvent SerialLineReceiver::classify(const protocol::FrameEvent& event, std::size_t held_before) {
    if (event.status == protocol::FrameStatus::NeedMore) return {};
    if (!is_rtu()) {
        // ASCII frames are delimited by characters, not silence: each bad one counts.
        return {event, event.is_error() ? LineError::Checksum : LineError::None};
    }
    if (broken_) {
        protocol::FrameEvent spoiled = event;
        spoiled.status = protocol::FrameStatus::Error;
        spoiled.pdu = {};
        spoiled.error = "frame spoiled by a gap over t1.5";
        return count_once(spoiled, LineError::ShortFrame);
    }
    if (event.is_frame()) return {event};
    // A burst of noise falls apart into as many framer errors as its bytes happen to suggest;
    // the line saw one bad message.
    return count_once(event, held_before < kMinRtuFrame && event.adu.empty() ? LineError::ShortFrame
                                                                             : LineError::Checksum);
}

LineEvent SerialLineReceiver::count_once(const protocol::FrameEvent& event, LineError error) {
    if (error_counted_) return {event, LineError::None};
    error_counted_ = true;
    return {event, error};
}

void SerialLineReceiver::reset() {
    framer_.reset();
    input_ = {};
    position_ = 0;
    held_ = 0;
    in_burst_ = false;
    silence_due_ = false;
    broken_ = false;
    error_counted_ = false;
}

void SerialLineReceiver::set_ascii_delimiter(std::uint8_t end) {
    framer_.set_ascii_delimiter(end);
}

std::uint8_t SerialLineReceiver::ascii_delimiter() const {
    return framer_.ascii_delimiter();
}

}  // namespace mblab::server
