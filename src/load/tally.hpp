#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "conformance/verdict.hpp"
#include "load/answer.hpp"
#include "load/histogram.hpp"

// What one worker thread counts about one node while a load run goes on.
namespace mblab::load {

// The first failure seen, with the exchange that shows it.
struct FailureRecord {
    FailureKind kind = FailureKind::Timeout;
    std::chrono::microseconds at{0};  // since the run started
    std::string exchange;             // the exchange's name; empty when no request was involved
    std::string reason;               // one line: "no answer: timeout after 1000 ms"
    conformance::Exchange evidence;
};

struct ExchangeTally {
    Tally sent;
    Tally failed;
};

class NodeTally {
  public:
    NodeTally(std::size_t exchanges, std::size_t cases)
        : not_applicable(cases),
          exchanges_(std::make_unique<ExchangeTally[]>(exchanges)),
          exchange_count_(exchanges) {}

    Tally sent;
    Tally answered;
    Tally late;        // answers that came after their request had timed out (not counted again)
    Tally handshakes;  // mbaps:// nodes: TLS handshakes completed, resumed ones included
    Tally resumed;
    Tally line_chars;   // serial lines: characters of the requests sent and the frames heard
    Tally line_frames;  // and how many frames they made
    std::array<Tally, kFailureKinds> failures;
    LatencyHistogram latency;

    ExchangeTally& exchange(std::size_t index) { return exchanges_[index]; }
    const ExchangeTally& exchange(std::size_t index) const { return exchanges_[index]; }
    std::size_t exchange_count() const { return exchange_count_; }

    std::uint64_t failure_total() const {
        std::uint64_t total = 0;
        for (const auto& tally : failures)
            total += tally.get();
        return total;
    }

    // Written by the owning thread only, read once it has stopped.
    std::optional<FailureRecord> first_failure;
    std::vector<std::string> not_applicable;  // by case: why it left the loop, empty if it did not

  private:
    std::unique_ptr<ExchangeTally[]> exchanges_;
    std::size_t exchange_count_;
};

}  // namespace mblab::load
