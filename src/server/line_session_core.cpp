#include "server/line_session_core.hpp"

#include <algorithm>

#include "device/reference_device.hpp"
#include "protocol/adu.hpp"
#include "protocol/function_code.hpp"
#include "transport/serial_port.hpp"

namespace mblab::server {

namespace {

// [SER] 2.5.2.1: an ASCII frame may pause up to 1 s between characters.
constexpr std::chrono::seconds kAsciiCharTimeout{1};

}  // namespace

SerialLineHooks device_line_hooks(device::ReferenceDevice& device) {
    SerialLineHooks hooks;
    hooks.on_frame_error = [&device](LineError error) {
        if (error == LineError::ShortFrame) {
            device.counters().count_short_frame();
        } else if (error == LineError::Checksum) {
            device.counters().count_crc_error();
        }
    };
    hooks.on_overrun = [&device] { device.counters().count_overrun(); };
    hooks.on_parity_error = [&device] { device.counters().count_parity_error(); };
    hooks.ascii_delimiter = [&device](std::uint8_t unit) {
        return device.counters().ascii_delimiter(unit);
    };
    return hooks;
}

LineSetup serial_line_setup(const transport::SerialUrl& url, SerialLineHooks hooks) {
    LineSetup setup;
    setup.hooks = std::move(hooks);
    if (url.paced) setup.pace = transport::character_time(url.line);
    if (url.kind == transport::SerialUrl::Kind::Ascii) {
        setup.framing = LineFraming::Ascii;
        setup.timing.silence = kAsciiCharTimeout;
        return setup;
    }
    const auto times = transport::rtu_char_times(url.line.baud);
    setup.framing = LineFraming::Rtu;
    setup.timing.silence = times.t35;
    if (url.strict_timing) setup.timing.char_gap = times.t15;
    setup.turnaround = times.t35;
    return setup;
}

LineSessionCore::LineSessionCore(device::RequestHandler& handler, const LineSetup& setup,
                                 LineCarrier carrier, LineLimits limits, ServerStats& stats,
                                 LineClock::time_point now)
    : handler_(handler),
      hooks_(setup.hooks),
      framing_(setup.framing),
      turnaround_(setup.turnaround),
      idle_timeout_(setup.idle_timeout),
      carrier_(carrier),
      limits_(limits),
      stats_(stats),
      receiver_(setup.framing, setup.timing, protocol::Direction::Request, setup.unknown_length),
      last_activity_(now) {}

void LineSessionCore::received(std::size_t count, LineClock::time_point now) {
    if (count == 0 || ending_) return;
    receiver_.receive(std::span<const std::uint8_t>(input_.data(), count), now);
    input_held_ = true;
    process(now);
}

void LineSessionCore::receive(std::span<const std::uint8_t> bytes, LineClock::time_point now) {
    const std::size_t count = std::min(bytes.size(), input_.size());
    std::copy_n(bytes.begin(), count, input_.begin());
    received(count, now);
}

void LineSessionCore::line_faults(std::uint32_t overruns, std::uint32_t parity_errors) {
    for (std::uint32_t i = 0; i < overruns && hooks_.on_overrun; ++i)
        hooks_.on_overrun();
    for (std::uint32_t i = 0; i < parity_errors && hooks_.on_parity_error; ++i)
        hooks_.on_parity_error();
}

void LineSessionCore::end_of_input() {
    receiver_.reset();
    input_held_ = false;
    ending_ = true;
}

void LineSessionCore::process(LineClock::time_point now) {
    while (input_held_ && !answer_owed_ && !ending_) {
        const LineEvent event = receiver_.next();
        if (event.empty()) {
            input_held_ = false;
            break;
        }
        handle(event, now);
    }
    if (input_held_) return;
    // Over TCP, a whole frame is bounded in time (LineLimits::frame_limit); a serial line paces
    // its bytes itself, and a long frame at a low baud rate takes seconds.
    const bool open = carrier_ == LineCarrier::Tcp && receiver_.has_partial();
    if (open && !frame_open_) frame_started_ = now;
    frame_open_ = open;
}

void LineSessionCore::on_time(LineClock::time_point now) {
    if (ending_ || answer_owed_ || input_held_) return;
    if (now >= receiver_.deadline()) {
        handle(receiver_.on_timeout(now), now);
        if (answer_owed_ || ending_) return;
    }
    if (idle_timeout_.count() > 0 && now >= last_activity_ + idle_timeout_) {
        ServerStats::bump(stats_.closed_idle);
        ending_ = true;
        return;
    }
    if (frame_open_ && now >= frame_started_ + limits_.frame_limit) {
        // A client that trickles a frame: the rest of it would be read out of step.
        ServerStats::bump(stats_.closed_slow_frame);
        ending_ = true;
    }
}

LineClock::time_point LineSessionCore::deadline() const {
    if (ending_ || answer_out_) return LineClock::time_point::max();
    if (answer_owed_) return answer_at_;
    auto deadline = receiver_.deadline();
    if (idle_timeout_.count() > 0) deadline = std::min(deadline, last_activity_ + idle_timeout_);
    if (frame_open_) deadline = std::min(deadline, frame_started_ + limits_.frame_limit);
    return deadline;
}

void LineSessionCore::handle(const LineEvent& event, LineClock::time_point now) {
    if (event.is_error()) {
        ServerStats::bump(stats_.frames_dropped);
        if (event.error != LineError::None && hooks_.on_frame_error) {
            hooks_.on_frame_error(event.error);
        }
        return;
    }
    if (!event.is_frame()) return;
    last_activity_ = now;
    ServerStats::bump(stats_.requests);
    const std::uint8_t unit = event.frame.header.unit;
    const auto reply = handler_.handle({unit, device::Link::Serial, peer_}, event.frame.pdu,
                                       std::span(response_).first(protocol::limits::kMaxPdu));
    switch (reply.action) {
        case device::ReplyAction::NoAnswer:
            return;
        case device::ReplyAction::Close:
            // A serial line cannot be hung up on; a TCP connection can.
            if (carrier_ == LineCarrier::Tcp) ending_ = true;
            return;
        case device::ReplyAction::Answer:
            break;
    }
    const auto ready_at = std::max(now + reply.delay, receiver_.last_byte_time() + turnaround_);
    owe_answer(unit, std::min(reply.size, protocol::limits::kMaxPdu), ready_at);
}

void LineSessionCore::owe_answer(std::uint8_t unit, std::size_t pdu_size,
                                 LineClock::time_point ready_at) {
    const auto pdu = std::span<const std::uint8_t>(response_.data(), pdu_size);
    if (pdu_size > 0 && (pdu.front() & protocol::kExceptionBit)) {
        ServerStats::bump(stats_.exceptions);
    }
    answer_size_ = protocol::write_adu({framing_, unit}, pdu, output_, receiver_.ascii_delimiter());
    // FC 08 sub 03 changes the ASCII delimiter for the frames after its own answer.
    if (framing_ == LineFraming::Ascii && hooks_.ascii_delimiter) {
        receiver_.set_ascii_delimiter(hooks_.ascii_delimiter(unit));
    }
    answer_owed_ = true;
    answer_at_ = ready_at;
}

std::span<const std::uint8_t> LineSessionCore::output(LineClock::time_point now) {
    if (!answer_owed_ || ending_ || now < answer_at_) return {};
    answer_out_ = true;
    return std::span<const std::uint8_t>(output_.data(), answer_size_);
}

void LineSessionCore::sent(LineClock::time_point now) {
    if (!answer_out_) return;
    answer_out_ = false;
    answer_owed_ = false;
    last_activity_ = now;
    process(now);
}

transport::Standing LineSessionCore::standing(LineClock::time_point now) const {
    using transport::Standing;
    // Answering a request, which is never the client's delay.
    if (ending_ || answer_owed_) return Standing::Busy;
    // Waiting for a request's first byte: nothing received to lose, nothing owed.
    if (!receiver_.has_partial()) return Standing::Idle;
    // Bytes without a whole request for long: a client that trickles holds the place unused.
    return now - last_activity_ >= limits_.partial_frame_timeout ? Standing::Stalled
                                                                 : Standing::Busy;
}

}  // namespace mblab::server
