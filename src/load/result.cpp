#include "load/result.hpp"

#include "support/name_table.hpp"

namespace mblab::load {

std::string_view load_verdict_label(LoadVerdict verdict) {
    static constexpr Named<LoadVerdict> kLabels[] = {{LoadVerdict::Pass, "PASS"},
                                                     {LoadVerdict::Fail, "FAIL"},
                                                     {LoadVerdict::Incomplete, "INCOMPLETE"}};
    return name_of(kLabels, verdict, "FAIL");
}

std::uint64_t NodeResult::failure_total() const {
    std::uint64_t total = 0;
    for (auto n : failures)
        total += n;
    return total;
}

LoadVerdict NodeResult::verdict(bool interrupted) const {
    if (failure_total() > 0) return LoadVerdict::Fail;
    return interrupted ? LoadVerdict::Incomplete : LoadVerdict::Pass;
}

LoadVerdict LoadResult::verdict() const {
    if (failures() > 0) return LoadVerdict::Fail;
    return interrupted ? LoadVerdict::Incomplete : LoadVerdict::Pass;
}

std::uint64_t LoadResult::sent() const {
    std::uint64_t total = 0;
    for (const auto& node : nodes)
        total += node.sent;
    return total;
}

std::uint64_t LoadResult::answered() const {
    std::uint64_t total = 0;
    for (const auto& node : nodes)
        total += node.answered;
    return total;
}

std::uint64_t LoadResult::failures() const {
    std::uint64_t total = 0;
    for (const auto& node : nodes)
        total += node.failure_total();
    return total;
}

void merge_tally(NodeResult& result, const NodeTally& tally, const LoadPlan& plan) {
    result.sent += tally.sent.get();
    result.answered += tally.answered.get();
    result.late += tally.late.get();
    result.handshakes += tally.handshakes.get();
    result.resumed += tally.resumed.get();
    result.line_chars += tally.line_chars.get();
    result.line_frames += tally.line_frames.get();
    for (std::size_t k = 0; k < kFailureKinds; ++k)
        result.failures[k] += tally.failures[k].get();
    tally.latency.snapshot_into(result.latency);
    result.exchange_sent.resize(tally.exchange_count(), 0);
    result.exchange_failed.resize(tally.exchange_count(), 0);
    for (std::size_t i = 0; i < tally.exchange_count(); ++i) {
        result.exchange_sent[i] += tally.exchange(i).sent.get();
        result.exchange_failed[i] += tally.exchange(i).failed.get();
    }
    for (std::size_t c = 0; c < tally.not_applicable.size(); ++c) {
        if (!tally.not_applicable[c].empty()) {
            result.not_applicable.push_back({plan.cases[c].id, tally.not_applicable[c]});
        }
    }
    if (tally.first_failure &&
        (!result.first_failure || tally.first_failure->at < result.first_failure->at)) {
        result.first_failure = tally.first_failure;
    }
}

}  // namespace mblab::load
