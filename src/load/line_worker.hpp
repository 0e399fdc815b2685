#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "conformance/session.hpp"
#include "load/exchanges.hpp"
#include "load/plan.hpp"
#include "load/thread.hpp"
#include "protocol/adu.hpp"
#include "support/prng.hpp"

namespace mblab::load {

// A node reached over RTU, ASCII or RTU over TCP (`LoadTarget::line`). A serial line has one
// master and carries one request at a time, so the node gets one thread that sends the node's
// protocol tests in catalogue order and, when generator connections go to this node, one request
// from the mix per connection after each test exchange: a round is one test exchange plus
// `traffic` mix requests. Each answer is judged as the load run judges Modbus/TCP answers (the
// Session hands it back in MBAP form). After a timeout, a malformed answer or a dropped link the
// link is opened afresh, so a late answer is never taken for the next request's.
class LoadLineWorker final : public LoadThread {
  public:
    LoadLineWorker(const LoadPlan& plan, std::size_t node, std::size_t traffic,
                   LoadClock::time_point start, std::chrono::nanoseconds send_interval,
                   std::uint64_t seed);

    void run(const std::atomic<bool>& draining) override;
    const NodeTally& tally(std::size_t node) const override { return *tallies_[node]; }

  private:
    // The next exchange of the round; false when there is nothing to send.
    bool next(std::uint32_t& index, bool& test);
    void pace();
    void exchange(std::uint32_t index, bool test);
    // A frame of `mbap_size` bytes in MBAP form crossed the line in its own framing.
    void count_frame(std::size_t mbap_size);

    const LoadPlan& plan_;
    std::size_t traffic_;
    LoadClock::time_point start_;
    std::chrono::nanoseconds send_interval_;
    Prng prng_;
    conformance::Session session_;
    std::vector<std::unique_ptr<NodeTally>> tallies_;
    NodeTally& tally_;
    protocol::Framing framing_;
    bool tests_ = true;
    std::size_t test_cursor_ = 0;
    std::size_t phase_ = 0;  // position in the round: 0 is the test exchange
    LoadClock::time_point next_send_{};
};

}  // namespace mblab::load
