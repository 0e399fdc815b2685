#include "transport/serial_master.hpp"

#include <algorithm>

#include "protocol/function_code.hpp"

namespace mblab::transport {

void SerialMaster::free_line_after(Clock::time_point at) {
    line_free_at_ = std::max(line_free_at_, at + timing_.inter_frame);
}

void SerialMaster::request_sent(std::uint8_t unit, std::uint8_t function, Clock::time_point now) {
    unit_ = unit;
    function_ = function;
    free_line_after(now);
    if (unit == 0) {
        state_ = State::Turnaround;
        deadline_ = now + timing_.turnaround;
        line_free_at_ = std::max(line_free_at_, deadline_);
        return;
    }
    state_ = State::WaitingReply;
    deadline_ = now + timing_.response_timeout;
}

void SerialMaster::heard(Clock::time_point now) {
    free_line_after(now);
}

SerialMaster::Verdict SerialMaster::on_frame(std::uint8_t unit, std::span<const std::uint8_t> pdu,
                                             Clock::time_point now) {
    heard(now);
    if (state_ != State::WaitingReply) return Verdict::Unasked;
    // An answer the timer has already given up on is as late as one after on_time().
    if (now >= deadline_) return Verdict::Unasked;
    if (unit != unit_) return Verdict::OtherAddress;
    if (pdu.empty() || (pdu.front() & ~protocol::kExceptionBit) != function_)
        return Verdict::OtherFunction;
    state_ = State::Idle;
    deadline_ = Clock::time_point::max();
    return Verdict::Answer;
}

SerialMaster::Clock::time_point SerialMaster::deadline() const {
    return state_ == State::Idle ? Clock::time_point::max() : deadline_;
}

SerialMaster::Timeout SerialMaster::on_time(Clock::time_point now) {
    if (state_ == State::Idle || now < deadline_) return Timeout::None;
    const State was = state_;
    state_ = State::Idle;
    deadline_ = Clock::time_point::max();
    if (was == State::Turnaround) return Timeout::TurnaroundOver;
    // The answer may be on its way: the next request waits for the line to fall silent.
    free_line_after(now);
    return Timeout::NoAnswer;
}

}  // namespace mblab::transport
