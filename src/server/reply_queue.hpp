#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "protocol/limits.hpp"

namespace mblab::server {

using Clock = std::chrono::steady_clock;

// One answer waiting to go out on a connection, built in place (no copy to send it).
struct PendingReply {
    Clock::time_point ready_at{};  // a fault delay holds it (and every answer behind it) back
    std::uint16_t size = 0;        // ADU bytes in `adu`
    bool close = false;            // a "close" fault: close the connection instead of answering
    // The handler answers later (RequestHandler::handle_or_defer): held back, and every answer
    // behind it, until the answer with this ticket comes.
    bool deferred = false;
    std::uint32_t ticket = 0;
    std::array<std::uint8_t, protocol::limits::kMaxTcpAdu> adu{};
};

// Answers of one connection in request order: a ring that idle connections hold none of, and that
// grows by doubling as a connection keeps more answers waiting, up to `capacity`. Allocating the
// whole ring at the first answer cost 11.7 KB per connection by default and 1.16 MB with
// --max-outstanding 4096, for clients that mostly have one request outstanding. Growth moves the
// slots, so nobody may keep a pointer to one across a push_back (the writer sends from them and
// is done before the reader queues more).
class ReplyQueue {
  public:
    explicit ReplyQueue(std::size_t capacity) : capacity_(capacity) {}

    bool empty() const { return count_ == 0; }
    std::size_t size() const { return count_; }

    // nullptr when `capacity` answers are queued.
    PendingReply* push_back();
    // Slots allocated now.
    std::size_t allocated() const { return slots_.size(); }
    void pop_back() { --count_; }  // undoes the last push_back
    PendingReply& at(std::size_t i) { return slots_[(head_ + i) % slots_.size()]; }
    const PendingReply& at(std::size_t i) const { return slots_[(head_ + i) % slots_.size()]; }
    PendingReply& front() { return at(0); }
    const PendingReply& front() const { return at(0); }
    void pop_front(std::size_t n);

  private:
    void grow();

    std::size_t capacity_;
    std::vector<PendingReply> slots_;
    std::size_t head_ = 0;
    std::size_t count_ = 0;
};

}  // namespace mblab::server
