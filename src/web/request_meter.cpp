#include "web/request_meter.hpp"

#include <algorithm>

#include "web/metrics_text.hpp"

namespace mblab::web {

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kPairs = 256 * 256;

bool is_exception(const device::Reply& reply, std::span<const std::uint8_t> pdu) {
    return reply.action == device::ReplyAction::Answer && reply.size >= 2 && !pdu.empty() &&
           (pdu[0] & 0x80) != 0;
}

}  // namespace

RequestMeter::RequestMeter()
    : requests_(std::make_unique<Counter[]>(kPairs)),
      exceptions_(std::make_unique<Counter[]>(kPairs)) {}

void RequestMeter::count(std::uint8_t unit, std::uint8_t function, bool exception,
                         std::chrono::nanoseconds latency) {
    const std::size_t pair = std::size_t{unit} * 256 + function;
    requests_[pair].fetch_add(1, std::memory_order_relaxed);
    if (exception) exceptions_[pair].fetch_add(1, std::memory_order_relaxed);
    const auto bounds = latency_bounds_seconds();
    const double seconds = std::chrono::duration<double>(latency).count();
    const auto bucket = static_cast<std::size_t>(
        std::lower_bound(bounds.begin(), bounds.end(), seconds) - bounds.begin());
    buckets_[bucket].fetch_add(1, std::memory_order_relaxed);
    sum_nanos_.fetch_add(static_cast<std::uint64_t>(std::max<std::int64_t>(latency.count(), 0)),
                         std::memory_order_relaxed);
}

std::vector<RequestCount> RequestMeter::counts() const {
    std::vector<RequestCount> out;
    for (std::size_t pair = 0; pair < kPairs; ++pair) {
        const auto requests = requests_[pair].load(std::memory_order_relaxed);
        if (requests == 0) continue;
        out.push_back({static_cast<std::uint8_t>(pair / 256), static_cast<std::uint8_t>(pair % 256),
                       requests, exceptions_[pair].load(std::memory_order_relaxed)});
    }
    return out;
}

LatencyCounts RequestMeter::latency() const {
    LatencyCounts out;
    std::uint64_t running = 0;
    for (std::size_t i = 0; i < latency_bounds_seconds().size(); ++i) {
        running += buckets_[i].load(std::memory_order_relaxed);
        out.cumulative.push_back(running);
    }
    // The count is the buckets' own sum, so +Inf never falls below a bucket while requests are
    // counted during the read.
    out.count = running + buckets_.back().load(std::memory_order_relaxed);
    out.sum_seconds = static_cast<double>(sum_nanos_.load(std::memory_order_relaxed)) / 1e9;
    return out;
}

void RequestMeter::reset() {
    for (std::size_t pair = 0; pair < kPairs; ++pair) {
        requests_[pair].store(0, std::memory_order_relaxed);
        exceptions_[pair].store(0, std::memory_order_relaxed);
    }
    for (auto& bucket : buckets_)
        bucket.store(0, std::memory_order_relaxed);
    sum_nanos_.store(0, std::memory_order_relaxed);
}

void MeterWatch::Timing::operator()(const device::Reply& reply,
                                    std::span<const std::uint8_t> pdu) const {
    meter->count(unit, function, is_exception(reply, pdu), Clock::now() - start + reply.delay);
}

MeterWatch::Timing MeterWatch::start(const device::RequestContext& context,
                                     std::span<const std::uint8_t> request) const {
    const std::uint8_t function = request.empty() ? 0 : request[0];
    return {&meter, context.unit, function, Clock::now()};
}

}  // namespace mblab::web
