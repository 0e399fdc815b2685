#include "server/reply_queue.hpp"

namespace mblab::server {

PendingReply* ReplyQueue::push_back() {
    if (slots_.empty()) slots_.resize(capacity_);
    if (count_ == slots_.size()) return nullptr;
    auto& slot = at(count_++);
    slot.close = false;
    slot.deferred = false;
    slot.size = 0;
    return &slot;
}

void ReplyQueue::pop_front(std::size_t n) {
    head_ = (head_ + n) % slots_.size();
    count_ -= n;
    if (count_ == 0) head_ = 0;
}

}  // namespace mblab::server
