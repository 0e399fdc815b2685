#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

// Latency of a load run, kept the way HDR histograms keep it: buckets that are exact for small
// values and a fixed share of the value wide above, so p99.9 of a million answers costs a few
// kilobytes and no sorting.
namespace mblab::load {

// A count that one thread writes and any thread reads. The owner's add is a plain load and
// store (no locked instruction), yet a status line may read it while the run goes on.
class Tally {
  public:
    void add(std::uint64_t n = 1) {
        value_.store(value_.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
    }
    void raise_to(std::uint64_t n) {
        if (n > value_.load(std::memory_order_relaxed)) {
            value_.store(n, std::memory_order_relaxed);
        }
    }
    std::uint64_t get() const { return value_.load(std::memory_order_relaxed); }

  private:
    std::atomic<std::uint64_t> value_{0};
};

// Bucket layout: values below 2^kSubBits microseconds have a bucket each; above, every power
// of two is cut into 2^(kSubBits-1) buckets, so a bucket is at most 1/64 (1.6 %) of its values
// wide. Values are clamped to 2^32 us (71 minutes).
struct LatencyBuckets {
    static constexpr unsigned kSubBits = 7;
    static constexpr unsigned kMaxBits = 32;
    static constexpr std::size_t kLinear = std::size_t{1} << kSubBits;
    static constexpr std::size_t kPerOctave = kLinear / 2;
    static constexpr std::size_t kCount = kLinear + (kMaxBits - kSubBits) * kPerOctave;
    static constexpr std::uint64_t kMaxValue = (std::uint64_t{1} << kMaxBits) - 1;

    static std::size_t index(std::uint64_t micros);
    // The largest value that lands in bucket `index`.
    static std::uint64_t upper(std::size_t index);
};

// Counts copied out of a histogram: merged across threads, subtracted for an interval.
class LatencySnapshot {
  public:
    LatencySnapshot() : counts_(LatencyBuckets::kCount, 0) {}

    std::uint64_t count() const { return total_; }
    std::uint64_t max() const { return max_; }
    // The value at quantile q (0 < q <= 1): the upper end of the bucket that holds it, never
    // above the largest value seen. 0 when empty.
    std::uint64_t percentile(double q) const;
    // Answers in bucket `index` (LatencyBuckets), for drawing the distribution.
    std::uint64_t in_bucket(std::size_t index) const { return counts_[index]; }
    // Values in the buckets wholly at or below `micros`: a Prometheus bucket's count (exact
    // below 128 us, else to within a bucket's 1.6 %).
    std::uint64_t count_at_most(std::uint64_t micros) const;
    // The sum of the values, each taken as its bucket's upper end.
    std::uint64_t approximate_sum() const;

    void add(const LatencySnapshot& other);
    // What `earlier` (an older snapshot of the same histogram) did not have yet. The maximum
    // stays the whole run's: an interval's own maximum is not known.
    LatencySnapshot since(const LatencySnapshot& earlier) const;

  private:
    friend class LatencyHistogram;
    std::vector<std::uint64_t> counts_;
    std::uint64_t total_ = 0;
    std::uint64_t max_ = 0;
};

// Written by one thread, read by any through snapshot().
class LatencyHistogram {
  public:
    void record(std::uint64_t micros) {
        buckets_[LatencyBuckets::index(micros)].add();
        max_.raise_to(micros);
    }
    void snapshot_into(LatencySnapshot& out) const;

  private:
    std::array<Tally, LatencyBuckets::kCount> buckets_{};
    Tally max_;
};

}  // namespace mblab::load
