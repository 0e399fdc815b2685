#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "robustness/monitor_cases.hpp"
#include "robustness/monitor_core.hpp"

// The essential-function monitor's cycles judged phase by phase, in IEC 62443-4-2 terms: PASS
// (the monitor held throughout), DEGRADED (lost for at most the declared limit, recovered
// unaided), FAIL (lost for longer, or not recovered without a restart).
namespace mblab::robustness {

struct MonitorPhase {
    std::string name;         // "baseline", "malformed input", "recovery"
    std::string requirement;  // "CR 7.1 denial-of-service protection", ...
    Clock::time_point begin{};
    Clock::time_point end{};
};

struct PhaseJudgement {
    MonitorPhase phase;
    std::size_t cycles = 0;
    std::size_t missed = 0;
    double missed_percent = 0;
    bool held = true;  // missed_percent within the tolerated percent
    std::chrono::microseconds median{0};
    std::chrono::microseconds worst{0};  // of the cycles that held
};

enum class MonitorVerdict : std::uint8_t { Pass, Degraded, Fail };
const char* verdict_name(MonitorVerdict verdict);  // "PASS", "DEGRADED", "FAIL"

struct MonitorJudgement {
    MonitorVerdict verdict = MonitorVerdict::Pass;
    std::vector<PhaseJudgement> phases;
    std::chrono::milliseconds longest_outage{0};  // missed cycles in a row, first to next held
    // From the start of the last phase (recovery) to the first cycle that held in it; nullopt
    // when none did.
    std::optional<std::chrono::milliseconds> recovery;
    std::string why;  // one line
    // The cases during which cycles were missed, when the run recorded its cases' times.
    std::vector<MissedDuring> missed_during;
};

// `phases` in order, the last the recovery phase. A phase holds when its missed cycles are within
// spec.miss_percent of its cycles.
MonitorJudgement judge_monitor(const std::vector<MonitorCycle>& cycles, const MonitorSpec& spec,
                               const std::vector<MonitorPhase>& phases,
                               std::chrono::milliseconds degraded_limit);

}  // namespace mblab::robustness
