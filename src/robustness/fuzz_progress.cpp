#include "robustness/fuzz_progress.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace mblab::robustness {

namespace {

std::string duration_text(std::chrono::milliseconds left) {
    const auto seconds = (left.count() + 999) / 1000;
    if (seconds < 60) return fmt::format("{}s", seconds);
    if (seconds < 3600) return fmt::format("{}m {:02}s", seconds / 60, seconds % 60);
    return fmt::format("{}h {:02}m", seconds / 3600, seconds / 60 % 60);
}

}  // namespace

std::string progress_text(std::size_t done, const ProgressBudget& budget,
                          std::chrono::milliseconds elapsed, const std::string& what) {
    std::optional<std::chrono::milliseconds> left;
    if (budget.cases && done > 0 && *budget.cases >= done) {
        // The pace so far, as a case of each class in turn makes the cases' costs even out.
        left = std::chrono::milliseconds(elapsed.count() * static_cast<long>(*budget.cases - done) /
                                         static_cast<long>(done));
    }
    if (budget.duration) {
        const auto by_time = std::max(std::chrono::milliseconds(0), *budget.duration - elapsed);
        left = left ? std::min(*left, by_time) : by_time;
    }
    const std::string count = budget.cases ? fmt::format("case {}/{}", done, *budget.cases)
                                           : fmt::format("case {}", done);
    if (!left) return fmt::format("{}: {}", count, what);
    return fmt::format("{}, about {} left: {}", count, duration_text(*left), what);
}

std::string ladder_progress_text(std::size_t done, std::size_t total,
                                 std::chrono::milliseconds step, const std::string& phase) {
    const auto left = step * static_cast<long>(total > done ? total - done : 0);
    return fmt::format("rung {}/{}, about {} left in the ladder: {}", done + 1, total,
                       duration_text(left), phase);
}

}  // namespace mblab::robustness
