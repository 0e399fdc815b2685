#include "load/runner.hpp"

#include <algorithm>
#include <memory>
#include <thread>

#include "load/line_worker.hpp"
#include "load/worker.hpp"

namespace mblab::load {

namespace {

using std::chrono::duration_cast;
using std::chrono::milliseconds;
using Role = LoadConnection::Role;

// The protocol tests get one connection per node; the generator's connections go round the
// nodes. Threads take connections in turn, so each carries a share of every kind. Line nodes
// have a thread of their own (add_line_threads).
std::vector<std::vector<ConnectionSpec>> share_out(const LoadPlan& plan, std::size_t threads) {
    std::vector<ConnectionSpec> all;
    const std::size_t nodes = plan.targets.size();
    if (plan.settings.tests && plan.test_exchanges > 0) {
        for (std::size_t node = 0; node < nodes; ++node) {
            if (!plan.targets[node].line) all.push_back({node, Role::Tests, 0});
        }
    }
    for (std::size_t i = 0; i < plan.settings.connections; ++i) {
        const std::size_t node = plan.node_of_traffic(i);
        if (!plan.targets[node].line) all.push_back({node, Role::Traffic, 0});
    }
    std::vector<std::vector<ConnectionSpec>> out(threads);
    for (std::size_t i = 0; i < all.size(); ++i) {
        all[i].seed = plan.settings.seed * 0x100000001B3ULL + i;
        out[i % threads].push_back(all[i]);
    }
    return out;
}

// Sums every worker's counts for the status line.
class StatusMeter {
  public:
    StatusMeter(const LoadPlan& plan, const std::vector<std::unique_ptr<LoadThread>>& workers)
        : plan_(plan), workers_(workers), last_(plan.targets.size()) {}

    LoadStatus measure(LoadClock::time_point now, LoadClock::time_point start) {
        LoadStatus status;
        status.elapsed = duration_cast<milliseconds>(now - start);
        const double seconds =
            std::chrono::duration<double>(
                now - (last_time_ == LoadClock::time_point{} ? start : last_time_))
                .count();
        for (std::size_t node = 0; node < plan_.targets.size(); ++node) {
            Sample sample;
            for (const auto& worker : workers_) {
                const NodeTally& tally = worker->tally(node);
                sample.sent += tally.sent.get();
                sample.answered += tally.answered.get();
                sample.failures += tally.failure_total();
                tally.latency.snapshot_into(sample.latency);
            }
            const LatencySnapshot interval = sample.latency.since(last_[node].latency);
            NodeStatus out;
            out.rate = seconds > 0
                           ? static_cast<double>(sample.answered - last_[node].answered) / seconds
                           : 0;
            out.failures = sample.failures;
            out.p50_us = interval.percentile(0.50);
            out.p99_us = interval.percentile(0.99);
            out.sent = sample.sent;
            out.answered = sample.answered;
            out.latency = sample.latency;
            status.rate += out.rate;
            status.failures += out.failures;
            status.nodes.push_back(out);
            last_[node] = std::move(sample);
        }
        last_time_ = now;
        return status;
    }

  private:
    struct Sample {
        std::uint64_t sent = 0;
        std::uint64_t answered = 0;
        std::uint64_t failures = 0;
        LatencySnapshot latency;
    };
    const LoadPlan& plan_;
    const std::vector<std::unique_ptr<LoadThread>>& workers_;
    std::vector<Sample> last_;
    LoadClock::time_point last_time_{};
};

// One thread per line node: its tests and the generator's connections that fall to it, as turns
// on the line. Its sends are paced as that many connections would be.
void add_line_threads(const LoadPlan& plan, LoadClock::time_point start,
                      std::chrono::nanoseconds interval,
                      std::vector<std::unique_ptr<LoadThread>>& threads) {
    const bool tests = plan.settings.tests && plan.test_exchanges > 0;
    for (std::size_t node = 0; node < plan.targets.size(); ++node) {
        if (!plan.targets[node].line) continue;
        std::size_t traffic = 0;
        for (std::size_t i = 0; i < plan.settings.connections; ++i)
            traffic += plan.node_of_traffic(i) == node ? 1 : 0;
        const std::size_t senders = traffic + (tests ? 1 : 0);
        if (senders == 0) continue;
        const auto seed = plan.settings.seed * 0x100000001B3ULL + 0x9E37 * (node + 1);
        threads.push_back(std::make_unique<LoadLineWorker>(
            plan, node, traffic, start, interval / static_cast<long>(senders), seed));
    }
}

}  // namespace

LoadResult LoadRunner::run(const std::atomic<bool>& stop, milliseconds status_period,
                           const std::function<void(const LoadStatus&)>& on_status) {
    const LoadSettings& settings = plan_.settings;
    const std::size_t connections = plan_.total_connections();
    const std::size_t threads = std::clamp<std::size_t>(
        settings.threads, 1, std::max<std::size_t>(plan_.tcp_connections(), 1));
    std::chrono::nanoseconds interval{0};
    if (settings.rate > 0 && connections > 0) {
        interval = std::chrono::nanoseconds(
            static_cast<std::int64_t>(1e9 * static_cast<double>(connections) / settings.rate));
    }

    const auto start = LoadClock::now();
    std::vector<std::unique_ptr<LoadThread>> workers;
    if (plan_.tcp_connections() > 0) {
        for (const auto& share : share_out(plan_, threads)) {
            workers.push_back(std::make_unique<LoadWorker>(plan_, share, start, interval));
        }
    }
    add_line_threads(plan_, start, interval, workers);
    std::atomic<bool> draining{false};
    std::vector<std::thread> threads_running;
    for (auto& worker : workers) {
        threads_running.emplace_back([&worker, &draining] { worker->run(draining); });
    }

    StatusMeter meter(plan_, workers);
    const auto end = start + settings.duration;
    auto next_status = start + status_period;
    auto now = start;
    // The stop flag is set from a signal handler, so it is polled rather than waited on.
    constexpr milliseconds kPoll{50};
    while (!stop.load(std::memory_order_relaxed) && now < end) {
        std::this_thread::sleep_until(std::min({next_status, end, now + kPoll}));
        now = LoadClock::now();
        if (now >= next_status && now < end) {
            on_status(meter.measure(now, start));
            next_status += status_period;
        }
    }

    LoadResult result;
    result.interrupted = now < end;
    result.elapsed = duration_cast<std::chrono::microseconds>(std::min(now, end) - start);
    draining.store(true, std::memory_order_relaxed);
    for (auto& thread : threads_running)
        thread.join();

    for (std::size_t node = 0; node < plan_.targets.size(); ++node) {
        NodeResult merged;
        merged.target = plan_.targets[node].url;
        for (const auto& worker : workers)
            merge_tally(merged, worker->tally(node), plan_);
        result.nodes.push_back(std::move(merged));
    }
    return result;
}

}  // namespace mblab::load
