#include "support/paced_line.hpp"

#include <algorithm>

namespace mblab::test {

namespace {

constexpr unsigned kBitsPerChar = 11;  // start, 8 data, parity, stop [SER 2.5.1]

}  // namespace

PacedLine::PacedLine(unsigned baud)
    : char_time_(std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(static_cast<double>(kBitsPerChar) / baud))) {}

void PacedLine::gap_before(std::size_t index, Clock::duration gap) {
    gaps_.push_back({index, gap});
}

void PacedLine::send(std::span<const std::uint8_t> bytes, Clock::time_point start) {
    for (const std::uint8_t byte : bytes) {
        auto begin = std::max(line_free_, start);
        for (const Gap& gap : gaps_) {
            if (gap.index == sent_) begin += gap.length;
        }
        line_free_ = begin + char_time_;
        arrivals_.push_back({byte, line_free_});
        ++sent_;
    }
}

PacedLine::Clock::time_point PacedLine::next_arrival() const {
    return arrivals_.empty() ? Clock::time_point::max() : arrivals_.front().at;
}

PacedLine::Clock::time_point PacedLine::last_arrival() const {
    return line_free_;
}

std::vector<PacedLine::Arrival> PacedLine::take(Clock::time_point now) {
    std::vector<Arrival> out;
    while (!arrivals_.empty() && arrivals_.front().at <= now) {
        out.push_back(arrivals_.front());
        arrivals_.pop_front();
    }
    return out;
}

}  // namespace mblab::test
