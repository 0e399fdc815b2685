#include "robustness/liveness.hpp"

#include <fmt/core.h>

#include <array>
#include <vector>

#include "protocol/adu.hpp"

namespace mblab::robustness {

namespace {

std::string hex(const std::vector<std::uint8_t>& bytes) {
    std::string out;
    for (auto byte : bytes)
        out += fmt::format("{}{:02X}", out.empty() ? "" : " ", byte);
    return out;
}

// Whether `answer` answers `sent` by its header: the same transaction id and protocol id 0 where
// the framing numbers requests; on a line, which pairs answers by order, the address asked.
bool paired(const protocol::AduHeader& sent, const protocol::AduHeader& answer) {
    if (sent.has_transaction())
        return answer.transaction_id == sent.transaction_id && answer.protocol_id == 0;
    return answer.unit == sent.unit;
}

}  // namespace

std::array<std::uint8_t, 5> known_good_read(std::uint16_t address) {
    return {0x03, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address), 0x00,
            0x01};
}

bool answers_known_good(std::span<const std::uint8_t> pdu) {
    return pdu.size() == 4 && pdu[0] == 0x03 && pdu[1] == 0x02;
}

LivenessOracle::LivenessOracle(CaseLinks& links, std::uint8_t unit, std::uint16_t address,
                               std::chrono::milliseconds timeout, RunClock clock)
    : links_(links), clock_(std::move(clock)), unit_(unit), address_(address), timeout_(timeout) {}

LivenessOracle::Outcome LivenessOracle::ask(client::Link& link, std::uint16_t address,
                                            std::string& detail, std::uint16_t* value) {
    protocol::AduHeader sent{link.framing(), unit_};
    if (sent.has_transaction()) sent.transaction_id = ++transaction_;
    const auto pdu = known_good_read(address);
    std::vector<std::uint8_t> frame(protocol::adu_size(sent.framing, pdu.size()));
    frame.resize(protocol::write_adu(sent, pdu, frame));
    client::LinkError error;
    if (!link.send(frame, error)) {
        detail = error.message;
        return Outcome::Closed;
    }
    const auto deadline = clock_.now() + timeout_;
    while (true) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock_.now());
        if (left.count() <= 0) return Outcome::Silent;
        const auto answer = link.receive_frame(left);
        if (answer.status == client::ReceiveStatus::Timeout) return Outcome::Silent;
        if (answer.status == client::ReceiveStatus::Closed) {
            detail = answer.detail.empty() ? "closed" : answer.detail;
            return Outcome::Closed;
        }
        if (answer.status == client::ReceiveStatus::Frame && paired(sent, answer.header) &&
            answers_known_good(answer.pdu)) {
            if (value != nullptr)
                *value = static_cast<std::uint16_t>(answer.pdu[2] << 8 | answer.pdu[3]);
            return Outcome::Good;
        }
        // Without a transaction id, a frame that is not the answer may be a late answer to the
        // case: read past it.
        if (sent.has_transaction()) {
            detail = hex(answer.bytes);
            return Outcome::Wrong;
        }
    }
}

client::Link* LivenessOracle::reach(client::LinkError& error) {
    constexpr std::array<std::chrono::milliseconds, 3> kPauses{std::chrono::milliseconds(250),
                                                               std::chrono::milliseconds(500),
                                                               std::chrono::milliseconds(750)};
    auto* link = links_.ask_on(error);
    for (auto pause : kPauses) {
        if (link != nullptr) break;
        clock_.sleep(pause);
        link = links_.ask_on(error);
    }
    return link;
}

Liveness LivenessOracle::check() {
    const auto start = clock_.now();
    Liveness out;
    auto dead = [&](std::string reason) {
        out.alive = false;
        out.reason = std::move(reason);
        out.waited = clock_.since(start);
        links_.done_asking();
        return out;
    };
    std::string detail;
    Outcome outcome = Outcome::Closed;
    int silences = 0;
    // A device that closed the connection the case used may be slow to free its slot, and may
    // close a fresh one it cannot serve yet (its slots still busy with the case's connections):
    // tried again until the declared timeout has passed before it counts.
    for (int attempt = 0;; ++attempt) {
        if (attempt >= 2) clock_.sleep(std::chrono::milliseconds(50));
        links_.done_asking();
        client::LinkError error;
        auto* link = reach(error);
        if (link == nullptr) {
            return dead(fmt::format("{} ({}) after trying for {} ms", links_.unreachable(),
                                    error.message, clock_.since(start).count()));
        }
        outcome = ask(*link, address_, detail);
        if (outcome == Outcome::Silent && links_.bystander() != nullptr && attempt == 0) {
            // A device that serves one connection at a time is busy with the bystander.
            links_.close_bystander();
            one_at_a_time_ = true;
            outcome = Outcome::Closed;
        }
        if (outcome == Outcome::Silent && ++silences < links_.asks()) continue;
        if (outcome != Outcome::Closed || (attempt >= 1 && clock_.since(start) >= timeout_)) break;
    }
    links_.done_asking();
    switch (outcome) {
        case Outcome::Good:
            break;
        case Outcome::Closed:
            return dead(fmt::format("closes {} before answering ({})", links_.asked_on(), detail));
        case Outcome::Silent:
            return dead(fmt::format(
                "does not answer the known-good read (FC 03, register {}, address {}) on {} "
                "within {} ms{}",
                address_, unit_, links_.asked_on(), timeout_.count(),
                links_.asks() > 1 ? ", asked twice" : ""));
        case Outcome::Wrong:
            return dead(fmt::format("answers the known-good read (FC 03, register {}) wrongly: {}",
                                    address_, detail));
    }
    if (auto* bystander = links_.bystander()) {
        switch (ask(*bystander, address_, detail)) {
            case Outcome::Good:
                break;
            case Outcome::Closed:
                // Closing an idle connection is the device's right.
                links_.close_bystander();
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
    if (links_.bystander() == nullptr) open_bystander();
    out.waited = clock_.since(start);
    return out;
}

Liveness LivenessOracle::wait_alive(std::chrono::milliseconds patience) {
    const auto start = clock_.now();
    while (true) {
        links_.close_bystander();
        auto liveness = check();
        if (liveness.alive || clock_.since(start) >= patience) {
            liveness.waited = clock_.since(start);
            return liveness;
        }
        links_.close_all();
        clock_.sleep(std::chrono::milliseconds(100));
    }
}

void LivenessOracle::open_bystander() {
    if (!one_at_a_time_) links_.open_bystander();
}

std::optional<std::uint16_t> LivenessOracle::read_register(std::uint16_t address) {
    client::LinkError error;
    auto* link = reach(error);
    std::string detail;
    std::uint16_t value = 0;
    const auto outcome = link != nullptr ? ask(*link, address, detail, &value) : Outcome::Closed;
    links_.done_asking();
    if (outcome != Outcome::Good) return std::nullopt;
    return value;
}

}  // namespace mblab::robustness
