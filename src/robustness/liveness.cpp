#include "robustness/liveness.hpp"

#include <fmt/core.h>

#include <thread>

#include "robustness/fuzz_case.hpp"

namespace mblab::robustness {

namespace {

using Clock = std::chrono::steady_clock;

conformance::EngineOptions engine_options(std::chrono::milliseconds timeout) {
    conformance::EngineOptions options;
    options.timeout = timeout;
    options.connect_timeout = timeout;
    return options;
}

conformance::Dut dut_for(std::uint8_t unit) {
    conformance::Dut dut;
    dut.unit = unit;
    return dut;
}

std::chrono::milliseconds since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
}

std::string hex(const std::vector<std::uint8_t>& bytes) {
    std::string out;
    for (auto byte : bytes)
        out += fmt::format("{}{:02X}", out.empty() ? "" : " ", byte);
    return out;
}

}  // namespace

std::array<std::uint8_t, 5> known_good_read(std::uint16_t address) {
    return {0x03, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address), 0x00,
            0x01};
}

bool answers_known_good(std::span<const std::uint8_t> pdu) {
    return pdu.size() == 4 && pdu[0] == 0x03 && pdu[1] == 0x02;
}

LivenessOracle::LivenessOracle(const client::Target& target, std::uint8_t unit,
                               std::uint16_t address, std::chrono::milliseconds timeout,
                               client::LinkObserver* observer)
    : fresh_(target, dut_for(unit), engine_options(timeout), observer),
      bystander_(target, dut_for(unit), engine_options(timeout), observer),
      unit_(unit),
      address_(address),
      timeout_(timeout) {}

LivenessOracle::Outcome LivenessOracle::ask(conformance::Session& session, std::string& detail) {
    const std::uint16_t transaction = ++transaction_;
    const auto frame = mbap_frame(transaction, unit_, known_good_read(address_));
    client::LinkError error;
    if (!session.send(frame, 1, error)) {
        detail = error.message;
        return Outcome::Closed;
    }
    const auto answer = session.receive_frame(timeout_);
    switch (answer.status) {
        case client::ReceiveStatus::Frame:
            if (answer.header.transaction_id == transaction && answer.header.protocol_id == 0 &&
                answers_known_good(answer.pdu))
                return Outcome::Good;
            detail = hex(answer.bytes);
            return Outcome::Wrong;
        case client::ReceiveStatus::Closed:
            detail = answer.detail.empty() ? "closed" : answer.detail;
            return Outcome::Closed;
        case client::ReceiveStatus::Timeout:
            return Outcome::Silent;
        case client::ReceiveStatus::Malformed:
            detail = hex(answer.bytes);
            return Outcome::Wrong;
    }
    return Outcome::Wrong;
}

Liveness LivenessOracle::check() {
    const auto start = Clock::now();
    Liveness out;
    auto dead = [&](std::string reason) {
        out.alive = false;
        out.reason = std::move(reason);
        out.waited = since(start);
        fresh_.close();
        return out;
    };
    std::string detail;
    Outcome outcome = Outcome::Closed;
    // A device that closed the connection the case used may be slow to free its slot, and may
    // close a fresh one it cannot serve yet (its slots still busy with the case's connections):
    // tried again until the declared timeout has passed before it counts.
    for (int attempt = 0; outcome == Outcome::Closed && (attempt < 2 || since(start) < timeout_);
         ++attempt) {
        if (attempt >= 2) std::this_thread::sleep_for(std::chrono::milliseconds(50));
        fresh_.close();
        client::LinkError error;
        if (!fresh_.reconnect(error)) {
            return dead(fmt::format("refuses connections ({}) after trying for {} ms",
                                    error.message, since(start).count()));
        }
        outcome = ask(fresh_, detail);
        if (outcome == Outcome::Silent && bystander_open_ && attempt == 0) {
            // A device that serves one connection at a time is busy with the bystander.
            bystander_.close();
            bystander_open_ = false;
            one_at_a_time_ = true;
            outcome = Outcome::Closed;
        }
    }
    fresh_.close();
    switch (outcome) {
        case Outcome::Good:
            break;
        case Outcome::Closed:
            return dead(fmt::format("closes a fresh connection before answering ({})", detail));
        case Outcome::Silent:
            return dead(
                fmt::format("does not answer the known-good read (FC 03, register {}) "
                            "on a fresh connection within {} ms",
                            address_, timeout_.count()));
        case Outcome::Wrong:
            return dead(fmt::format("answers the known-good read (FC 03, register {}) wrongly: {}",
                                    address_, detail));
    }
    if (bystander_open_) {
        switch (ask(bystander_, detail)) {
            case Outcome::Good:
                break;
            case Outcome::Closed:
                // Closing an idle connection is the device's right.
                bystander_.close();
                bystander_open_ = false;
                break;
            case Outcome::Silent:
                return dead(
                    fmt::format("stopped answering a connection opened before the case "
                                "(no answer within {} ms) while fresh ones are served",
                                timeout_.count()));
            case Outcome::Wrong:
                return dead(
                    fmt::format("answers the known-good read wrongly on a connection "
                                "opened before the case: {}",
                                detail));
        }
    }
    if (!bystander_open_) open_bystander();
    out.waited = since(start);
    return out;
}

Liveness LivenessOracle::wait_alive(std::chrono::milliseconds patience) {
    const auto start = Clock::now();
    while (true) {
        bystander_.close();
        bystander_open_ = false;
        auto liveness = check();
        if (liveness.alive || since(start) >= patience) {
            liveness.waited = since(start);
            return liveness;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

void LivenessOracle::open_bystander() {
    if (one_at_a_time_) return;
    client::LinkError error;
    bystander_open_ = bystander_.connect(error);
}

std::optional<std::uint16_t> LivenessOracle::read_register(std::uint16_t address) {
    fresh_.close();
    client::LinkError error;
    if (!fresh_.reconnect(error)) return std::nullopt;
    const std::uint16_t transaction = ++transaction_;
    if (!fresh_.send(mbap_frame(transaction, unit_, known_good_read(address)), 1, error))
        return std::nullopt;
    const auto answer = fresh_.receive_frame(timeout_);
    fresh_.close();
    if (answer.status != client::ReceiveStatus::Frame ||
        answer.header.transaction_id != transaction || !answers_known_good(answer.pdu))
        return std::nullopt;
    return static_cast<std::uint16_t>(answer.pdu[2] << 8 | answer.pdu[3]);
}

void LivenessOracle::close() {
    fresh_.close();
    bystander_.close();
    bystander_open_ = false;
}

}  // namespace mblab::robustness
