#include "robustness/liveness.hpp"

#include <fmt/core.h>

#include <array>
#include <vector>

#include "protocol/adu.hpp"

namespace mblab::robustness {

using conformance::Served;

LivenessOracle::LivenessOracle(CaseLinks& links, std::uint8_t unit, std::uint16_t address,
                               std::chrono::milliseconds timeout, RunClock clock)
    : links_(links), clock_(std::move(clock)), unit_(unit), address_(address), timeout_(timeout) {}

conformance::ServingAnswer LivenessOracle::ask(client::Link& link, std::uint16_t address) {
    protocol::AduHeader header{link.framing(), unit_};
    if (header.has_transaction()) header.transaction_id = ++transaction_;
    return conformance::ask_serving(
        link, {.header = header, .address = address, .timeout = timeout_, .now = clock_.now});
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
    conformance::ServingAnswer answer;
    answer.served = Served::Closed;
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
        answer = ask(*link, address_);
        if (answer.served == Served::Silent && links_.bystander() != nullptr && attempt == 0) {
            // A device that serves one connection at a time is busy with the bystander.
            links_.close_bystander();
            one_at_a_time_ = true;
            answer.served = Served::Closed;
        }
        if (answer.served == Served::Silent && ++silences < links_.asks()) continue;
        if (answer.served != Served::Closed || (attempt >= 1 && clock_.since(start) >= timeout_))
            break;
    }
    links_.done_asking();
    switch (answer.served) {
        case Served::Yes:
            break;
        case Served::Closed:
            return dead(
                fmt::format("closes {} before answering ({})", links_.asked_on(), answer.detail()));
        case Served::Silent:
            return dead(fmt::format(
                "does not answer the known-good read (FC 03, register {}, address {}) on {} "
                "within {} ms{}",
                address_, unit_, links_.asked_on(), timeout_.count(),
                links_.asks() > 1 ? ", asked twice" : ""));
        case Served::Wrong:
            return dead(fmt::format("answers the known-good read (FC 03, register {}) wrongly: {}",
                                    address_, answer.detail()));
    }
    if (auto* bystander = links_.bystander()) {
        const auto on_bystander = ask(*bystander, address_);
        switch (on_bystander.served) {
            case Served::Yes:
                break;
            case Served::Closed:
                // Closing an idle connection is the device's right.
                links_.close_bystander();
                break;
            case Served::Silent:
                return dead(
                    fmt::format("stopped answering a connection opened before the case "
                                "(no answer within {} ms) while fresh ones are served",
                                timeout_.count()));
            case Served::Wrong:
                return dead(
                    fmt::format("answers the known-good read wrongly on a connection "
                                "opened before the case: {}",
                                on_bystander.detail()));
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
    const auto answer = link != nullptr ? ask(*link, address) : conformance::ServingAnswer{};
    links_.done_asking();
    if (link == nullptr || answer.served != Served::Yes) return std::nullopt;
    return answer.value;
}

}  // namespace mblab::robustness
