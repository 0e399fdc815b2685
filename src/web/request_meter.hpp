#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "device/request_handler.hpp"

// Requests and exceptions per unit and function code, and the time the server took to answer,
// counted on the Modbus thread(s) and read by the HTTP thread for /metrics and /api/counters.
// Relaxed atomics: a reader may see one counter a request ahead of another, never a torn value.
namespace mblab::web {

struct RequestCount {
    std::uint8_t unit = 0;
    std::uint8_t function = 0;
    std::uint64_t requests = 0;
    std::uint64_t exceptions = 0;
};

struct LatencyCounts {
    std::vector<std::uint64_t> cumulative;  // per latency_bounds_seconds()
    std::uint64_t count = 0;
    double sum_seconds = 0;
};

class RequestMeter {
  public:
    RequestMeter();

    void count(std::uint8_t unit, std::uint8_t function, bool exception,
               std::chrono::nanoseconds latency);
    // Only the pairs that saw a request, by unit then function.
    std::vector<RequestCount> counts() const;
    LatencyCounts latency() const;
    void reset();

  private:
    using Counter = std::atomic<std::uint64_t>;
    std::unique_ptr<Counter[]> requests_;  // [unit * 256 + function]
    std::unique_ptr<Counter[]> exceptions_;
    std::array<Counter, 18> buckets_{};  // one per bound, then above the last
    Counter sum_nanos_{0};
};

// Counts what passes between a server and its handler. The time is the handler's plus the
// delay the reply asks for (a fault rule's "delay"), what a client waits beyond the network.
struct MeterWatch {
    // A request on its way: counted when its reply comes.
    struct Timing {
        RequestMeter* meter = nullptr;
        std::uint8_t unit = 0;
        std::uint8_t function = 0;
        std::chrono::steady_clock::time_point start = {};

        void operator()(const device::Reply& reply, std::span<const std::uint8_t> pdu) const;
    };

    RequestMeter& meter;

    Timing start(const device::RequestContext& context,
                 std::span<const std::uint8_t> request) const;
};

using MeteredHandler = device::WatchingHandler<MeterWatch>;

}  // namespace mblab::web
