#include "load/line_worker.hpp"

#include <thread>

#include "client/target.hpp"
#include "protocol/limits.hpp"

namespace mblab::load {

namespace {

using std::chrono::duration_cast;
using std::chrono::microseconds;

// A line that cannot be opened is tried again after this.
constexpr std::chrono::milliseconds kReopenDelay{100};
// How long an idle line (every test N/A, no traffic) sleeps between looks at the drain flag.
constexpr std::chrono::milliseconds kIdleNap{20};
constexpr std::chrono::milliseconds kMaxSendDebt{50};

conformance::EngineOptions line_options(const LoadSettings& settings) {
    conformance::EngineOptions options;
    options.timeout = settings.timeout;
    options.connect_timeout = std::max(settings.timeout, std::chrono::milliseconds(1000));
    options.pipeline_depth = 1;
    return options;
}

}  // namespace

LoadLineWorker::LoadLineWorker(const LoadPlan& plan, std::size_t node, std::size_t traffic,
                               LoadClock::time_point start, std::chrono::nanoseconds send_interval,
                               std::uint64_t seed)
    : plan_(plan),
      traffic_(traffic),
      start_(start),
      send_interval_(send_interval),
      prng_(seed),
      session_(*plan.targets[node].line, conformance::Dut{}, line_options(plan.settings)),
      tallies_([&] {
          std::vector<std::unique_ptr<NodeTally>> out;
          for (std::size_t i = 0; i < plan.targets.size(); ++i)
              out.push_back(std::make_unique<NodeTally>(plan.exchanges.size(), plan.cases.size()));
          return out;
      }()),
      tally_(*tallies_[node]),
      framing_(client::framing_of(*plan.targets[node].line)),
      tests_(plan.settings.tests && plan.test_exchanges > 0),
      next_send_(start) {}

bool LoadLineWorker::next(std::uint32_t& index, bool& test) {
    for (std::size_t tried = 0; tried <= traffic_; ++tried) {
        const std::size_t phase = phase_;
        phase_ = (phase_ + 1) % (traffic_ + 1);
        if (phase != 0) {
            index = next_mix_exchange(plan_, prng_);
            test = false;
            return true;
        }
        if (tests_ && next_test_exchange(plan_, tally_, test_cursor_, index)) {
            test = true;
            return true;
        }
        tests_ = false;  // every case is N/A on this node
    }
    return false;
}

void LoadLineWorker::pace() {
    if (send_interval_.count() <= 0) return;
    const auto now = LoadClock::now();
    // After a stall (a timeout) the debt is forgiven rather than paid back as a burst.
    if (next_send_ + kMaxSendDebt < now) next_send_ = now - kMaxSendDebt;
    std::this_thread::sleep_until(next_send_);
    next_send_ += send_interval_;
}

void LoadLineWorker::exchange(std::uint32_t index, bool test) {
    const LoadExchange& chosen = plan_.exchanges[index];
    if (test) {
        // A case that tests the MBAP header has no equivalent on the line.
        if (auto why = conformance::mbap_only_reason(session_, false, false, chosen.request)) {
            tally_.not_applicable[chosen.test_case] = "N/A: " + *why;
            return;
        }
    }
    client::LinkError error;
    if (!session_.connect(error)) {
        count_failure(tally_, plan_, start_, FailureKind::Refused, nullptr,
                      {client::ReceiveStatus::Closed, {}, error.message}, LoadClock::now(),
                      "cannot open the line: ");
        std::this_thread::sleep_for(kReopenDelay);
        return;
    }
    pace();
    const LoadSent sent{index, 0};
    const auto sent_at = LoadClock::now();
    count_frame(chosen.request.size());
    tally_.sent.add();
    tally_.exchange(index).sent.add();
    if (!session_.send(chosen.request, 1, error)) {
        count_failure(tally_, plan_, start_, FailureKind::Dropped, &sent,
                      {client::ReceiveStatus::Closed, {}, error.message}, LoadClock::now());
        session_.close();
        return;
    }
    const client::Received received = session_.receive_frame(plan_.settings.timeout);
    const auto now = LoadClock::now();
    const LoadSeen seen{received.status, received.bytes, received.detail};
    std::optional<FailureKind> failure;
    switch (received.status) {
        case client::ReceiveStatus::Frame:
            count_frame(received.bytes.size());
            tally_.answered.add();
            tally_.latency.record(
                static_cast<std::uint64_t>(duration_cast<microseconds>(now - sent_at).count()));
            failure = judge_load_answer(plan_, tally_, test, index, received.bytes);
            break;
        case client::ReceiveStatus::Timeout:
            failure = FailureKind::Timeout;
            break;
        case client::ReceiveStatus::Malformed:
            failure = FailureKind::Malformed;
            break;
        case client::ReceiveStatus::Closed:
            failure = FailureKind::Dropped;
            break;
    }
    if (!failure) return;
    count_failure(tally_, plan_, start_, *failure, &sent, seen, now);
    // What is left on the line (a late or partial answer) must not meet the next request.
    if (received.status != client::ReceiveStatus::Frame) session_.close();
}

void LoadLineWorker::count_frame(std::size_t mbap_size) {
    if (mbap_size <= protocol::limits::kMbapHeader) return;
    tally_.line_frames.add();
    tally_.line_chars.add(protocol::adu_size(framing_, mbap_size - protocol::limits::kMbapHeader));
}

void LoadLineWorker::run(const std::atomic<bool>& draining) {
    while (!draining.load(std::memory_order_relaxed)) {
        std::uint32_t index = 0;
        bool test = false;
        if (!next(index, test)) {
            std::this_thread::sleep_for(kIdleNap);
            continue;
        }
        exchange(index, test);
    }
    session_.close();
}

}  // namespace mblab::load
