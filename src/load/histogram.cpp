#include "load/histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace mblab::load {

std::size_t LatencyBuckets::index(std::uint64_t micros) {
    micros = std::min(micros, kMaxValue);
    if (micros < kLinear) return static_cast<std::size_t>(micros);
    const unsigned top = static_cast<unsigned>(std::bit_width(micros)) - 1;  // >= kSubBits
    const unsigned shift = top - (kSubBits - 1);
    const std::size_t within = static_cast<std::size_t>(micros >> shift) - kPerOctave;
    return kLinear + (top - kSubBits) * kPerOctave + within;
}

std::uint64_t LatencyBuckets::upper(std::size_t index) {
    if (index < kLinear) return index;
    const std::size_t octave = (index - kLinear) / kPerOctave;
    const std::size_t within = (index - kLinear) % kPerOctave;
    const unsigned shift = static_cast<unsigned>(octave) + 1;
    const std::uint64_t low = static_cast<std::uint64_t>(kPerOctave + within) << shift;
    return low + ((std::uint64_t{1} << shift) - 1);
}

std::uint64_t LatencySnapshot::percentile(double q) const {
    if (total_ == 0) return 0;
    const auto wanted = std::max<std::uint64_t>(
        1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total_))));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < counts_.size(); ++i) {
        seen += counts_[i];
        if (seen >= wanted) return std::min(LatencyBuckets::upper(i), max_);
    }
    return max_;
}

std::uint64_t LatencySnapshot::count_at_most(std::uint64_t micros) const {
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < counts_.size() && LatencyBuckets::upper(i) <= micros; ++i)
        total += counts_[i];
    return total;
}

std::uint64_t LatencySnapshot::approximate_sum() const {
    std::uint64_t sum = 0;
    for (std::size_t i = 0; i < counts_.size(); ++i)
        sum += counts_[i] * std::min(LatencyBuckets::upper(i), max_);
    return sum;
}

void LatencySnapshot::add(const LatencySnapshot& other) {
    for (std::size_t i = 0; i < counts_.size(); ++i)
        counts_[i] += other.counts_[i];
    total_ += other.total_;
    max_ = std::max(max_, other.max_);
}

LatencySnapshot LatencySnapshot::since(const LatencySnapshot& earlier) const {
    LatencySnapshot out;
    for (std::size_t i = 0; i < counts_.size(); ++i) {
        out.counts_[i] = counts_[i] - std::min(counts_[i], earlier.counts_[i]);
        out.total_ += out.counts_[i];
    }
    out.max_ = max_;
    return out;
}

void LatencyHistogram::snapshot_into(LatencySnapshot& out) const {
    for (std::size_t i = 0; i < buckets_.size(); ++i) {
        const std::uint64_t n = buckets_[i].get();
        out.counts_[i] += n;
        out.total_ += n;
    }
    out.max_ = std::max(out.max_, max_.get());
}

}  // namespace mblab::load
