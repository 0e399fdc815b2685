#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

// The console's progress line during a robustness run: cases done out of the total, and the time
// left, from the run's pace so far or from its time budget, whichever ends it first; before that,
// the storm ladder's rungs done out of the total and the time they have left.
namespace mblab::robustness {

struct ProgressBudget {
    std::optional<std::size_t> cases;                   // the run ends after this many cases
    std::optional<std::chrono::milliseconds> duration;  // or after this long
};

// "case 120/1000, about 1m 20s left: truncated: FC 0x03 alone"; without a case total, "case 120,
// about 40s left: ..." from the time budget; without a pace yet (nothing done), no time left.
std::string progress_text(std::size_t done, const ProgressBudget& budget,
                          std::chrono::milliseconds elapsed, const std::string& what);

// The ladder's line before each rung: "rung 3/12, about 20s left in the ladder: storm fc06 500/s"
// (the rungs left, this one included, at `step` each).
std::string ladder_progress_text(std::size_t done, std::size_t total,
                                 std::chrono::milliseconds step, const std::string& phase);

}  // namespace mblab::robustness
