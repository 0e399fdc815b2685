#include "server/traffic_log.hpp"

#include <string_view>

#include "protocol/function_code.hpp"

namespace mblab::server {

namespace {

using Clock = std::chrono::steady_clock;

// A request as it came, before its answer; `no_peer` stands for a link without an address.
TrafficEntry request_entry(const device::RequestContext& context,
                           std::span<const std::uint8_t> request, std::string_view no_peer) {
    TrafficEntry entry;
    entry.time = std::chrono::system_clock::now();
    entry.peer = std::string(context.peer.empty() ? no_peer : context.peer);
    entry.unit = context.unit;
    entry.request.assign(request.begin(), request.end());
    return entry;
}

}  // namespace

TrafficLog::TrafficLog(std::optional<RotatingFile> out, TrafficFormat format, std::size_t ring)
    : out_(std::move(out)), format_(format), ring_size_(ring) {}

void TrafficLog::record(TrafficEntry entry) {
    // Formatted outside the lock: only the write and the ring are shared.
    std::string line;
    if (out_) line = format_ == TrafficFormat::Ndjson ? traffic_ndjson(entry) : traffic_text(entry);
    const std::lock_guard lock(mutex_);
    ++recorded_;
    if (out_) out_->write_line(line);
    if (ring_size_ == 0) return;
    if (ring_.size() == ring_size_) ring_.pop_front();
    ring_.push_back(std::move(entry));
}

void TrafficLog::record_own_answer(const device::RequestContext& context,
                                   std::span<const std::uint8_t> request,
                                   protocol::ExceptionCode code) {
    auto entry = request_entry(context, request, "-");
    entry.response = {static_cast<std::uint8_t>(request.front() | protocol::kExceptionBit),
                      static_cast<std::uint8_t>(code)};
    record(std::move(entry));
}

std::vector<TrafficEntry> TrafficLog::recent(std::uint64_t after, std::uint64_t& last) const {
    const std::lock_guard lock(mutex_);
    last = recorded_;
    const std::uint64_t first_kept = recorded_ - ring_.size() + 1;
    std::vector<TrafficEntry> out;
    for (std::size_t i = 0; i < ring_.size(); ++i) {
        if (first_kept + i > after) out.push_back(ring_[i]);
    }
    return out;
}

void LogWatch::Pending::operator()(const device::Reply& reply, std::span<const std::uint8_t> pdu) {
    entry.action = reply.action;
    if (reply.action == device::ReplyAction::Answer) {
        const auto size = std::min(reply.size, pdu.size());
        entry.response.assign(pdu.begin(), pdu.begin() + static_cast<std::ptrdiff_t>(size));
    }
    entry.latency = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start) +
                    std::chrono::duration_cast<std::chrono::microseconds>(reply.delay);
    log->record(std::move(entry));
}

LogWatch::Pending LogWatch::start(const device::RequestContext& context,
                                  std::span<const std::uint8_t> request) const {
    return {&log, request_entry(context, request, line_name), Clock::now()};
}

}  // namespace mblab::server
