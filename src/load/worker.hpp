#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "load/connection.hpp"
#include "load/plan.hpp"
#include "load/tally.hpp"
#include "load/thread.hpp"
#include "transport/epoll_set.hpp"

namespace mblab::load {

struct ConnectionSpec {
    std::size_t node = 0;
    LoadConnection::Role role = LoadConnection::Role::Traffic;
    std::uint64_t seed = 1;
};

// One thread's share of a load run's Modbus/TCP connections, on one epoll loop.
class LoadWorker final : public LoadThread {
  public:
    LoadWorker(const LoadPlan& plan, const std::vector<ConnectionSpec>& connections,
               LoadClock::time_point start, std::chrono::nanoseconds send_interval);

    // Runs until `draining` is set and every request in flight is answered or timed out.
    void run(const std::atomic<bool>& draining) override;

    const NodeTally& tally(std::size_t node) const override { return *tallies_[node]; }

  private:
    bool all_settled() const;

    transport::EpollSet epoll_;
    SocketPorts ports_{epoll_};
    WorkerContext context_;
    std::vector<std::unique_ptr<NodeTally>> tallies_;
    std::vector<std::unique_ptr<LoadConnection>> connections_;
    std::chrono::microseconds tick_;
};

}  // namespace mblab::load
