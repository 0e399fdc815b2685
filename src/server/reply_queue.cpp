#include "server/reply_queue.hpp"

#include <algorithm>

namespace mblab::server {

namespace {

// Most clients wait for each answer: two slots hold an answer and one queued behind it.
constexpr std::size_t kFirstSlots = 2;

}  // namespace

PendingReply* ReplyQueue::push_back() {
    if (count_ == slots_.size()) {
        if (count_ >= capacity_) return nullptr;
        grow();
    }
    auto& slot = at(count_++);
    slot.close = false;
    slot.deferred = false;
    slot.size = 0;
    return &slot;
}

void ReplyQueue::grow() {
    const auto size = std::min(capacity_, std::max(kFirstSlots, 2 * slots_.size()));
    std::vector<PendingReply> grown(size);
    for (std::size_t i = 0; i < count_; ++i)
        grown[i] = at(i);  // in order from the head, so the ring starts at 0 again
    slots_ = std::move(grown);
    head_ = 0;
}

void ReplyQueue::pop_front(std::size_t n) {
    head_ = (head_ + n) % slots_.size();
    count_ -= n;
    if (count_ == 0) head_ = 0;
}

}  // namespace mblab::server
