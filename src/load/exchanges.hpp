#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "client/raw_link.hpp"
#include "load/answer.hpp"
#include "load/plan.hpp"
#include "load/tally.hpp"
#include "support/prng.hpp"

// What every kind of load connection does with exchanges, whatever carries them (a Modbus/TCP
// connection on an epoll loop, or a serial line): choose the next one, judge its answer, and
// count a failure with the evidence of the node's first.
namespace mblab::load {

using LoadClock = std::chrono::steady_clock;

// What came back instead of the right answer; views, copied only into the evidence.
struct LoadSeen {
    client::ReceiveStatus status = client::ReceiveStatus::Timeout;
    std::span<const std::uint8_t> bytes;
    std::string_view detail;
};

// An exchange as it went on the wire: which one, and the transaction id it carried.
struct LoadSent {
    std::uint32_t exchange = 0;
    std::uint16_t tid = 0;
};

// The generator's next request, drawn from the mix by weight.
std::uint32_t next_mix_exchange(const LoadPlan& plan, Prng& prng);

// The protocol tests' next exchange: round the cases in catalogue order from `cursor`, skipping
// the ones this node took out of the loop as N/A. False when every case is N/A here.
bool next_test_exchange(const LoadPlan& plan, const NodeTally& tally, std::size_t& cursor,
                        std::uint32_t& out);

// Judges `frame`, the whole MBAP answer to exchange `exchange`: a failure kind, or nothing.
// For the protocol tests, exception 01 to a case's first step, when the case allows it, takes the
// case out of this node's loop as N/A instead.
std::optional<FailureKind> judge_load_answer(const LoadPlan& plan, NodeTally& tally, bool tests,
                                             std::uint32_t exchange,
                                             std::span<const std::uint8_t> frame);

// Counts a failure of `kind` (and of the exchange, when one was sent); the node's first keeps
// its evidence. A given `reason` goes before the detail as the one-line reason; otherwise the
// reason is judged from the exchange.
void count_failure(NodeTally& tally, const LoadPlan& plan, LoadClock::time_point start,
                   FailureKind kind, const LoadSent* sent, const LoadSeen& seen,
                   LoadClock::time_point now, std::string_view reason = {});

}  // namespace mblab::load
