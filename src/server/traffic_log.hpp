#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "device/request_handler.hpp"
#include "protocol/exception_code.hpp"
#include "server/rotating_file.hpp"
#include "server/traffic_entry.hpp"

// `mblab serve --log`: each request and its answer, written as a line (text or NDJSON) and kept
// in a ring of the last ones for the dashboard. Called from the Modbus thread(s) and read from
// the HTTP thread, so it takes a lock; the line is written at once (a log that waits for a
// buffer to fill is no use when watching a device live).
namespace mblab::server {

enum class TrafficFormat : std::uint8_t { Text, Ndjson };

inline constexpr std::size_t kTrafficRing = 200;

class TrafficLog {
  public:
    // `out` set: each entry is written to it; `ring`: entries kept for recent().
    TrafficLog(std::optional<RotatingFile> out, TrafficFormat format, std::size_t ring);

    void record(TrafficEntry entry);
    // An answer a session gave itself, not the handler (ServerOptions::on_own_answer): 06 busy,
    // 01 refused by role, 03 for an unfinished frame. Logged as the handler's are, taking no time.
    void record_own_answer(const device::RequestContext& context,
                           std::span<const std::uint8_t> request, protocol::ExceptionCode code);
    // The kept entries after number `after` (0: all kept), oldest first, and the number of the
    // last one recorded, so that a reader asks only for what is new.
    std::vector<TrafficEntry> recent(std::uint64_t after, std::uint64_t& last) const;

  private:
    mutable std::mutex mutex_;
    std::optional<RotatingFile> out_;
    TrafficFormat format_;
    std::size_t ring_size_;
    std::deque<TrafficEntry> ring_;
    std::uint64_t recorded_ = 0;
};

// Hands each request and its answer to the log. The latency is the handler's time plus the
// delay the reply asks for (a fault rule's "delay"): what a client waits beyond the network.
// `line_name` stands for the peer where the link has no address (a serial line).
struct LogWatch {
    // What is known of a request before its answer: the answer completes it.
    struct Pending {
        TrafficLog* log = nullptr;
        TrafficEntry entry = {};
        std::chrono::steady_clock::time_point start = {};

        void operator()(const device::Reply& reply, std::span<const std::uint8_t> pdu);
    };

    TrafficLog& log;
    std::string line_name;

    Pending start(const device::RequestContext& context,
                  std::span<const std::uint8_t> request) const;
};

using LoggedHandler = device::WatchingHandler<LogWatch>;

}  // namespace mblab::server
