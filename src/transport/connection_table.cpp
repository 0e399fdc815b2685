#include "transport/connection_table.hpp"

#include <algorithm>
#include <iterator>

namespace mblab::transport {

void ConnectionTable::add(TrackedConnection& connection) {
    connection.prev_ = nullptr;
    connection.next_ = head_;
    if (head_) head_->prev_ = &connection;
    head_ = &connection;
    ++size_;
}

void ConnectionTable::remove(TrackedConnection& connection) {
    if (connection.prev_) {
        connection.prev_->next_ = connection.next_;
    } else if (head_ == &connection) {
        head_ = connection.next_;
    } else {
        return;  // not in the table
    }
    if (connection.next_) connection.next_->prev_ = connection.prev_;
    connection.prev_ = connection.next_ = nullptr;
    --size_;
}

Standing ConnectionTable::close_one_for_newcomer(Clock::time_point now) {
    // A linear scan: it runs only when the table is full, and a full table is rare.
    // The kinds a newcomer may displace, the first to go first; the oldest of a kind goes.
    constexpr Standing kOrder[] = {Standing::Ending, Standing::Handshaking, Standing::Stalled,
                                   Standing::Unused, Standing::Idle};
    TrackedConnection* oldest[std::size(kOrder)] = {};
    for (auto* c = head_; c; c = c->next_) {
        if (c->closing_) continue;
        const auto* kind = std::find(std::begin(kOrder), std::end(kOrder), c->standing(now));
        if (kind == std::end(kOrder)) continue;
        auto*& best = oldest[kind - std::begin(kOrder)];
        if (!best || c->last_activity() < best->last_activity()) best = c;
    }
    for (std::size_t i = 0; i < std::size(kOrder); ++i) {
        if (!oldest[i]) continue;
        close(*oldest[i]);
        return kOrder[i];
    }
    return Standing::Busy;
}

void ConnectionTable::close_all() {
    // A connection may remove itself as it closes: take its successor first.
    for (auto* c = head_; c;) {
        auto* next = c->next_;
        close(*c);
        c = next;
    }
}

void ConnectionTable::close(TrackedConnection& connection) {
    if (connection.closing_) return;
    connection.closing_ = true;
    connection.close();
}

}  // namespace mblab::transport
