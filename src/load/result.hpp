#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "load/answer.hpp"
#include "load/histogram.hpp"
#include "load/plan.hpp"
#include "load/tally.hpp"

namespace mblab::load {

// CTP 8.4: PASS only with no failure anywhere for the whole duration. A run stopped early
// without failures is INCOMPLETE: it did not show what the policy asks.
enum class LoadVerdict : std::uint8_t { Pass, Fail, Incomplete };

std::string_view load_verdict_label(LoadVerdict verdict);  // "PASS", "FAIL", "INCOMPLETE"

// Everything counted about one node, over every thread.
struct NodeResult {
    std::string target;
    std::uint64_t sent = 0;
    std::uint64_t answered = 0;
    std::uint64_t late = 0;
    std::uint64_t handshakes = 0;  // mbaps:// nodes
    std::uint64_t resumed = 0;
    std::uint64_t line_chars = 0;  // serial lines (load/line_use.hpp)
    std::uint64_t line_frames = 0;
    std::array<std::uint64_t, kFailureKinds> failures{};
    LatencySnapshot latency;
    std::vector<std::uint64_t> exchange_sent;  // by LoadPlan::exchanges index
    std::vector<std::uint64_t> exchange_failed;
    std::vector<LeftOut> not_applicable;  // test cases that left the loop on this node
    std::optional<FailureRecord> first_failure;

    std::uint64_t failure_total() const;
    std::uint64_t failures_of(FailureKind kind) const {
        return failures[static_cast<std::size_t>(kind)];
    }
    LoadVerdict verdict(bool interrupted) const;
};

struct LoadResult {
    std::vector<NodeResult> nodes;
    std::chrono::microseconds elapsed{0};  // of loading, without the final wait for answers
    bool interrupted = false;              // stopped before the duration (Ctrl-C)

    LoadVerdict verdict() const;
    std::uint64_t sent() const;
    std::uint64_t answered() const;
    std::uint64_t failures() const;
};

// Adds one thread's counts for `node` (the first failure kept is the earliest).
void merge_tally(NodeResult& result, const NodeTally& tally, const LoadPlan& plan);

}  // namespace mblab::load
