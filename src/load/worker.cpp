#include "load/worker.hpp"

#include <algorithm>
#include <array>
#include <cerrno>

namespace mblab::load {

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

// How often timeouts, reconnects and paced sends are looked at: often enough that a timeout
// is counted within a twentieth of it, and every millisecond when --rate paces the sends.
microseconds tick_period(const LoadSettings& settings) {
    if (settings.rate > 0) return milliseconds(1);
    const auto twentieth = std::chrono::duration_cast<microseconds>(settings.timeout) / 20;
    return std::clamp<microseconds>(twentieth, milliseconds(1), milliseconds(10));
}

int millis_until(LoadClock::time_point when, LoadClock::time_point now) {
    if (when <= now) return 0;
    // Rounded up: epoll would wake a little early and the tick would wait a whole round.
    const auto wait = std::chrono::ceil<milliseconds>(when - now);
    return static_cast<int>(wait.count());
}

}  // namespace

LoadWorker::LoadWorker(const LoadPlan& plan, const std::vector<ConnectionSpec>& connections,
                       LoadClock::time_point start, std::chrono::nanoseconds send_interval)
    : context_{plan, ports_, start, send_interval, true}, tick_(tick_period(plan.settings)) {
    for (std::size_t i = 0; i < plan.targets.size(); ++i) {
        tallies_.push_back(std::make_unique<NodeTally>(plan.exchanges.size(), plan.cases.size()));
    }
    for (const auto& spec : connections) {
        connections_.push_back(std::make_unique<LoadConnection>(context_, *tallies_[spec.node],
                                                                spec.node, spec.role, spec.seed));
    }
}

bool LoadWorker::all_settled() const {
    return std::all_of(connections_.begin(), connections_.end(),
                       [](const auto& connection) { return connection->settled(); });
}

void LoadWorker::run(const std::atomic<bool>& draining) {
    auto now = LoadClock::now();
    for (auto& connection : connections_)
        connection->start(now);
    auto next_tick = now + tick_;
    std::array<epoll_event, 256> events{};
    for (;;) {
        if (context_.running && draining.load(std::memory_order_relaxed)) {
            context_.running = false;
            next_tick = now;
        }
        const int n = epoll_.wait(events, millis_until(next_tick, now));
        for (int i = 0; i < n; ++i) {
            static_cast<LoadConnection*>(events[static_cast<std::size_t>(i)].data.ptr)
                ->on_event(events[static_cast<std::size_t>(i)].events, LoadClock::now());
        }
        now = LoadClock::now();
        if (now < next_tick) continue;
        for (auto& connection : connections_)
            connection->tick(now);
        next_tick = now + tick_;
        if (!context_.running && all_settled()) return;
    }
}

}  // namespace mblab::load
