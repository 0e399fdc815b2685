#include "robustness/monitor_core.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "robustness/fuzz_case.hpp"

namespace mblab::robustness {

namespace {

std::vector<std::uint8_t> words(std::uint8_t function, std::uint16_t a, std::uint16_t b) {
    return {function, static_cast<std::uint8_t>(a >> 8), static_cast<std::uint8_t>(a),
            static_cast<std::uint8_t>(b >> 8), static_cast<std::uint8_t>(b)};
}

}  // namespace

MonitorCore::MonitorCore(MonitorSpec spec, Clock::time_point now) : spec_(spec), next_start_(now) {
    spec_.budget = std::min(spec_.budget, spec_.period);
}

std::vector<std::uint8_t> MonitorCore::request(std::span<const std::uint8_t> pdu) {
    return mbap_frame(++transaction_, spec_.unit, pdu);
}

void MonitorCore::miss(std::string why) {
    cycles_.back().missed = std::move(why);
    waiting_ = Waiting::Nothing;
    pending_read_ = false;
}

std::vector<std::uint8_t> MonitorCore::poll(Clock::time_point now) {
    if (waiting_ != Waiting::Nothing && !pending_read_ && now >= deadline())
        miss(fmt::format("no answer within {} ms", spec_.budget.count()));
    if (pending_read_) {
        pending_read_ = false;
        sent_ = now;
        return request(words(0x03, spec_.address, 1));
    }
    if (waiting_ != Waiting::Nothing || now < next_start_) return {};
    // A cycle that would start late (the owner woke late) starts now, on the next period after.
    cycles_.push_back({now, std::nullopt, {}});
    while (next_start_ <= now)
        next_start_ += spec_.period;
    input_.clear();
    sent_ = now;
    device_ = std::chrono::microseconds(0);
    // A value that changes every cycle, never 0: a register stuck at its reset value is caught.
    value_ = static_cast<std::uint16_t>((cycles_.size() - 1) % 0xFFFF + 1);
    if (spec_.read_only) {
        waiting_ = Waiting::Read;
        return request(words(0x03, spec_.address, 1));
    }
    waiting_ = Waiting::Write;
    return request(words(0x06, spec_.address, value_));
}

void MonitorCore::received(std::span<const std::uint8_t> bytes, Clock::time_point now) {
    input_.insert(input_.end(), bytes.begin(), bytes.end());
    while (input_.size() >= 7) {
        const std::size_t length = static_cast<std::size_t>(input_[4] << 8 | input_[5]);
        if (length < 2 || input_.size() < 6 + length) return;
        const std::uint16_t transaction = static_cast<std::uint16_t>(input_[0] << 8 | input_[1]);
        const std::vector<std::uint8_t> pdu(input_.begin() + 7,
                                            input_.begin() + static_cast<long>(6 + length));
        input_.erase(input_.begin(), input_.begin() + static_cast<long>(6 + length));
        // An answer to a request of a cycle already missed is late, not this cycle's.
        if (transaction == transaction_ && waiting_ != Waiting::Nothing) answer(pdu, now);
    }
}

void MonitorCore::answer(std::span<const std::uint8_t> pdu, Clock::time_point now) {
    const auto expected = words(0x06, spec_.address, value_);
    // An arrival the kernel dated before the send (clocks read apart) counts as none.
    device_ += std::max(std::chrono::microseconds(0),
                        std::chrono::duration_cast<std::chrono::microseconds>(now - sent_));
    if (waiting_ == Waiting::Write) {
        if (!std::equal(pdu.begin(), pdu.end(), expected.begin(), expected.end())) {
            miss(pdu.size() >= 2 && pdu[0] == 0x86
                     ? fmt::format("FC 06 answered exception {:02X}", pdu[1])
                     : std::string("FC 06 answered with something other than its echo"));
            return;
        }
        // The read-back goes out at once: poll() sends it.
        waiting_ = Waiting::Read;
        pending_read_ = true;
        return;
    }
    if (pdu.size() != 4 || pdu[0] != 0x03 || pdu[1] != 2) {
        miss(pdu.size() >= 2 && pdu[0] == 0x83
                 ? fmt::format("FC 03 answered exception {:02X}", pdu[1])
                 : std::string("FC 03 answered with something other than one register"));
        return;
    }
    const auto read = static_cast<std::uint16_t>(pdu[2] << 8 | pdu[3]);
    if (!spec_.read_only && read != value_) {
        miss(fmt::format("read {} after writing {}", read, value_));
        return;
    }
    // Read after the budget (the owner drains the connection before it calls poll()): late.
    if (device_ > spec_.budget) {
        miss(fmt::format("answered in {:.1f} ms, over the {} ms budget", device_.count() / 1000.0,
                         spec_.budget.count()));
        return;
    }
    waiting_ = Waiting::Nothing;
    cycles_.back().latency = device_;
}

void MonitorCore::connection_lost(Clock::time_point now) {
    (void)now;
    input_.clear();
    if (waiting_ != Waiting::Nothing) miss("the connection closed");
}

Clock::time_point MonitorCore::deadline() const {
    if (pending_read_) return cycles_.back().started;
    if (waiting_ != Waiting::Nothing) return sent_ + (spec_.budget - device_);
    return next_start_;
}

}  // namespace mblab::robustness
