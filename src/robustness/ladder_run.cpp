#include "robustness/ladder_run.hpp"

#include "robustness/fuzz_case.hpp"

namespace mblab::robustness {

namespace {

// One request and its answer's PDU on a connection of its own; nullopt when none came.
std::optional<std::vector<std::uint8_t>> ask_once(const StormTarget& target,
                                                  const std::vector<std::uint8_t>& pdu) {
    auto opened = target.dial();
    if (!opened) return std::nullopt;
    auto& link = *opened.value();
    client::LinkError error;
    std::optional<std::vector<std::uint8_t>> out;
    if (link.send(mbap_frame(1, target.unit, pdu), error)) {
        const auto answer = link.next_frame(target.timeout);
        if (answer.status == client::ReceiveStatus::Frame) out = answer.pdu;
    }
    link.close();
    return out;
}

}  // namespace

std::vector<PlannedLadder> plan_ladders(const std::vector<Ladder>& ladders, const Recon& recon,
                                        const WritePolicy& policy, std::uint16_t monitor) {
    std::vector<PlannedLadder> out;
    for (const auto& ladder : ladders) {
        PlannedLadder planned{ladder, {}};
        if (is_request_storm(ladder.kind))
            planned.request = plan_request_storm(ladder.kind, recon, policy, monitor);
        out.push_back(std::move(planned));
    }
    return out;
}

std::size_t rungs_to_run(const std::vector<PlannedLadder>& ladders) {
    std::size_t total = 0;
    for (const auto& planned : ladders) {
        if (planned.request.not_run.empty()) total += planned.ladder.rates.size();
    }
    return total;
}

LadderRun run_ladders(const StormTarget& target, std::vector<PlannedLadder> ladders,
                      std::chrono::milliseconds step, const LadderProgress& progress) {
    LadderRun out;
    std::size_t total = rungs_to_run(ladders);
    for (auto& planned : ladders) {
        const auto kind = planned.ladder.kind;
        auto& request = planned.request;
        // Read just before the first rung, so that what is written back is what is there, and the
        // place proven to take the write (or, for a file's or a FIFO's read, to answer it).
        if (is_request_storm(kind) && request.not_run.empty() && request.pdu.empty()) {
            choose_place(kind, request, [&](const std::vector<std::uint8_t>& pdu) {
                return ask_once(target, pdu);
            });
            if (!request.not_run.empty()) total -= planned.ladder.rates.size();
        }
        if (!request.not_run.empty()) {
            out.not_run.push_back({kind, request.not_run});
            continue;
        }
        for (double rate : planned.ladder.rates) {
            if (progress) progress(out.rungs.size(), total, storm_phase_name(kind, rate));
            out.rungs.push_back(storm(target, kind, rate, step, request.pdu));
            if (names_address(kind)) out.rungs.back().address = request.address;
        }
    }
    return out;
}

}  // namespace mblab::robustness
