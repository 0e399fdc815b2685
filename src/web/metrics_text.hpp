#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

// The Prometheus text exposition format (version 0.0.4), written by hand: a family's HELP and
// TYPE lines once, then its samples. Label values are escaped as the format says (\\, \", \n).
namespace mblab::web {

using Labels = std::vector<std::pair<std::string, std::string>>;

// Bucket bounds of every latency histogram mblab exposes, in seconds: 50 us to 10 s, a few per
// decade, so a loopback answer and a slow serial gateway both land inside.
std::span<const double> latency_bounds_seconds();

class MetricsText {
  public:
    // Starts a family; `type` is counter, gauge or histogram.
    void family(const std::string& name, const std::string& type, const std::string& help);
    void sample(const std::string& name, const Labels& labels, double value);
    // A histogram's samples: `cumulative[i]` answers at most latency_bounds_seconds()[i], then
    // +Inf (= count), _sum and _count.
    void histogram(const std::string& name, const Labels& labels,
                   std::span<const std::uint64_t> cumulative, std::uint64_t count,
                   double sum_seconds);

    const std::string& text() const { return text_; }

  private:
    std::string text_;
};

// The content type Prometheus scrapers expect for this format.
inline constexpr const char* kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace mblab::web
