#include "robustness/monitor_verdict.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace mblab::robustness {

namespace {

std::chrono::milliseconds ms(Clock::duration span) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(span);
}

}  // namespace

const char* verdict_name(MonitorVerdict verdict) {
    switch (verdict) {
        case MonitorVerdict::Pass:
            return "PASS";
        case MonitorVerdict::Degraded:
            return "DEGRADED";
        case MonitorVerdict::Fail:
            break;
    }
    return "FAIL";
}

MonitorJudgement judge_monitor(const std::vector<MonitorCycle>& cycles, const MonitorSpec& spec,
                               const std::vector<MonitorPhase>& phases,
                               std::chrono::milliseconds degraded_limit) {
    MonitorJudgement out;
    for (const auto& phase : phases) {
        PhaseJudgement judged{phase};
        std::vector<std::chrono::microseconds> latencies;
        for (const auto& c : cycles) {
            if (c.pending() || c.started < phase.begin || c.started >= phase.end) continue;
            ++judged.cycles;
            if (c.held()) {
                latencies.push_back(*c.latency);
            } else {
                ++judged.missed;
            }
        }
        if (judged.cycles > 0) {
            judged.missed_percent =
                100.0 * static_cast<double>(judged.missed) / static_cast<double>(judged.cycles);
        }
        judged.held = judged.missed_percent <= spec.miss_percent;
        if (!latencies.empty()) {
            std::sort(latencies.begin(), latencies.end());
            judged.median = latencies[latencies.size() / 2];
            judged.worst = latencies.back();
        }
        out.phases.push_back(std::move(judged));
    }
    // Outages: missed cycles in a row, from the first's start to the next held one's start.
    // The first missed cycle of the run of them under way, or none (a plain pointer: g++ 12 takes
    // an optional time point for one used uninitialised).
    const MonitorCycle* lost_since = nullptr;
    const MonitorCycle* last_done = nullptr;
    for (const auto& c : cycles) {
        if (c.pending()) continue;
        last_done = &c;
        if (!c.held()) {
            if (lost_since == nullptr) lost_since = &c;
        } else if (lost_since != nullptr) {
            out.longest_outage = std::max(out.longest_outage, ms(c.started - lost_since->started));
            lost_since = nullptr;
        }
    }
    const bool recovered = last_done != nullptr && last_done->held();
    if (lost_since != nullptr && !phases.empty()) {
        out.longest_outage =
            std::max(out.longest_outage, ms(phases.back().end - lost_since->started));
    }
    if (!phases.empty()) {
        const auto& last = phases.back();
        for (const auto& c : cycles) {
            if (c.started >= last.begin && c.started < last.end && c.held()) {
                out.recovery = ms(c.started - last.begin) +
                               std::chrono::duration_cast<std::chrono::milliseconds>(*c.latency);
                break;
            }
        }
    }
    const bool held = std::all_of(out.phases.begin(), out.phases.end(),
                                  [](const PhaseJudgement& p) { return p.held; });
    if (held && recovered) {
        out.verdict = MonitorVerdict::Pass;
        out.why = "the monitor held in every phase";
    } else if (recovered && out.longest_outage <= degraded_limit) {
        out.verdict = MonitorVerdict::Degraded;
        out.why = fmt::format(
            "the monitor was lost for {} ms at most (the limit is {} ms) and came back unaided",
            out.longest_outage.count(), degraded_limit.count());
    } else if (recovered) {
        out.verdict = MonitorVerdict::Fail;
        out.why = fmt::format("the monitor was lost for {} ms, longer than the limit of {} ms",
                              out.longest_outage.count(), degraded_limit.count());
    } else {
        out.verdict = MonitorVerdict::Fail;
        out.why = "the monitor did not come back without a restart";
    }
    return out;
}

}  // namespace mblab::robustness
