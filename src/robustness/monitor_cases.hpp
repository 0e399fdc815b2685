#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "robustness/fuzz_case.hpp"
#include "robustness/monitor_core.hpp"

// Which cases the essential-function monitor missed its cycles during: the run records each
// case's time (from its first frame to the next case's, so its check and what the device does
// after it count as its own), and each missed cycle is laid against them.
namespace mblab::robustness {

// The phase the cases run in.
inline constexpr std::string_view kCasesPhase = "malformed input";

struct CaseSpan {
    std::size_t number = 0;  // 1 for the run's first case
    BadInput kind = BadInput::Mutation;
    std::string name;
    Clock::time_point begin{};
    Clock::time_point end{};
};

struct MissedDuring {
    std::size_t case_number = 0;
    BadInput kind = BadInput::Mutation;
    std::string case_name;
    std::size_t missed = 0;  // cycles missed while it ran
    std::string reason;      // the first one's
};

// The cases during which a cycle was missed, in the run's order. A cycle spans its start to its
// budget's end; it is laid against every case that ran in that time (none for a cycle before the
// first case or after the last: the baseline, the ladder, the recovery).
std::vector<MissedDuring> missed_during(const std::vector<MonitorCycle>& cycles,
                                        const std::vector<CaseSpan>& cases,
                                        std::chrono::milliseconds budget);

// "case 12 (pipelined: 200 requests at once): 3 cycle(s) missed, the first: no answer within 40
// ms"
std::string missed_during_text(const MissedDuring& during);

}  // namespace mblab::robustness
