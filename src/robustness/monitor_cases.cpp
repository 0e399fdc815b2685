#include "robustness/monitor_cases.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>

namespace mblab::robustness {

std::vector<MissedDuring> missed_during(const std::vector<MonitorCycle>& cycles,
                                        const std::vector<CaseSpan>& cases,
                                        std::chrono::milliseconds budget) {
    // By index into `cases`, so the list comes out in the run's order.
    std::map<std::size_t, MissedDuring> found;
    const auto blame = [&](std::size_t at, const MonitorCycle& cycle) {
        auto [entry, added] = found.try_emplace(at);
        if (added) {
            entry->second.case_number = cases[at].number;
            entry->second.kind = cases[at].kind;
            entry->second.case_name = cases[at].name;
            entry->second.reason = cycle.missed;
        }
        ++entry->second.missed;
    };
    for (const auto& cycle : cycles) {
        if (cycle.held() || cycle.pending()) continue;
        const auto from = cycle.started;
        const auto to = cycle.started + budget;
        // The first case that ends after the cycle starts.
        const auto first = std::partition_point(cases.begin(), cases.end(),
                                                [&](const CaseSpan& c) { return c.end <= from; });
        for (auto c = first; c != cases.end() && c->begin < to; ++c)
            blame(static_cast<std::size_t>(c - cases.begin()), cycle);
    }
    std::vector<MissedDuring> out;
    for (auto& entry : found)
        out.push_back(std::move(entry.second));
    return out;
}

std::string missed_during_text(const MissedDuring& during) {
    return fmt::format("case {} ({}: {}): {} cycle(s) missed, the first: {}", during.case_number,
                       class_name(during.kind), during.case_name, during.missed, during.reason);
}

}  // namespace mblab::robustness
