#include "robustness/line_liveness.hpp"

#include <fmt/core.h>

#include <thread>

#include "robustness/line_cases.hpp"

namespace mblab::robustness {

namespace {

using Clock = std::chrono::steady_clock;

std::chrono::milliseconds since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
}

}  // namespace

LineOracle::LineOracle(std::uint8_t unit, std::uint16_t address, std::chrono::milliseconds timeout,
                       std::chrono::milliseconds quiet)
    : unit_(unit), address_(address), timeout_(timeout), quiet_(quiet) {}

void LineOracle::drain(client::Link& link) {
    // Bounded: a device that talks without end is judged by the read that follows.
    for (int i = 0; i < 64 && link.is_open(); ++i) {
        const auto got = link.receive_any(quiet_);
        if (got.status == client::ReceiveStatus::Timeout && got.bytes.empty()) return;
        if (got.status == client::ReceiveStatus::Closed) return;
    }
}

LineOracle::Outcome LineOracle::ask(client::Link& link, std::string& detail) {
    drain(link);
    std::this_thread::sleep_for(quiet_);
    const auto frame = line_frame(link.framing(), unit_, known_good_read(address_));
    client::LinkError error;
    if (!link.send(frame, error)) {
        detail = error.message;
        return Outcome::Closed;
    }
    // A late answer to the case, or a frame the device garbled, is not the answer: read on.
    const auto deadline = Clock::now() + timeout_;
    while (Clock::now() < deadline) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        auto answer = link.receive_frame(std::max(left, std::chrono::milliseconds(1)));
        if (answer.status == client::ReceiveStatus::Timeout) return Outcome::Silent;
        if (answer.status == client::ReceiveStatus::Closed) {
            detail = answer.detail.empty() ? "closed" : answer.detail;
            return Outcome::Closed;
        }
        if (answer.status == client::ReceiveStatus::Frame && answer.header.unit == unit_ &&
            answers_known_good(answer.pdu))
            return Outcome::Good;
    }
    return Outcome::Silent;
}

Liveness LineOracle::check(client::Link& link) {
    const auto start = Clock::now();
    Liveness out;
    std::string detail;
    Outcome outcome = Outcome::Silent;
    for (int attempt = 0; attempt < 2 && outcome == Outcome::Silent; ++attempt)
        outcome = ask(link, detail);
    out.waited = since(start);
    switch (outcome) {
        case Outcome::Good:
            break;
        case Outcome::Closed:
            out.alive = false;
            out.reason = fmt::format("closes the link before answering ({})", detail);
            break;
        case Outcome::Silent:
            out.alive = false;
            out.reason = fmt::format(
                "does not answer the known-good read (FC 03, register {}, address {}) within {} "
                "ms, asked twice",
                address_, unit_, timeout_.count());
            break;
    }
    return out;
}

}  // namespace mblab::robustness
