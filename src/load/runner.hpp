#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "load/histogram.hpp"
#include "load/plan.hpp"
#include "load/result.hpp"

namespace mblab::load {

// How a run is going, for the live status line: rates and latency over the last period.
struct NodeStatus {
    double rate = 0;  // answers/s
    std::uint64_t failures = 0;
    std::uint64_t p50_us = 0;
    std::uint64_t p99_us = 0;
    // Since the run started, for --metrics.
    std::uint64_t sent = 0;
    std::uint64_t answered = 0;
    LatencySnapshot latency;
};

struct LoadStatus {
    std::chrono::milliseconds elapsed{0};
    double rate = 0;
    std::uint64_t failures = 0;
    std::vector<NodeStatus> nodes;
};

// Runs a plan: the protocol tests on one connection per node and the generator's connections,
// spread over the worker threads, for the plan's duration or until `stop` becomes true; then
// waits for the answers in flight (at most the timeout) and gathers the counts.
class LoadRunner {
  public:
    explicit LoadRunner(const LoadPlan& plan) : plan_(plan) {}

    LoadResult run(const std::atomic<bool>& stop, std::chrono::milliseconds status_period,
                   const std::function<void(const LoadStatus&)>& on_status);

  private:
    const LoadPlan& plan_;
};

}  // namespace mblab::load
