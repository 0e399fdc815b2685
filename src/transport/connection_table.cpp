#include "transport/connection_table.hpp"

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
    TrackedConnection* oldest_handshaking = nullptr;
    TrackedConnection* oldest_stalled = nullptr;
    TrackedConnection* oldest_idle = nullptr;
    auto older = [](TrackedConnection* best, TrackedConnection* c) {
        return !best || c->last_activity() < best->last_activity() ? c : best;
    };
    for (auto* c = head_; c; c = c->next_) {
        if (c->closing_) continue;
        const auto standing = c->standing(now);
        if (standing == Standing::Handshaking) oldest_handshaking = older(oldest_handshaking, c);
        if (standing == Standing::Stalled) oldest_stalled = older(oldest_stalled, c);
        if (standing == Standing::Idle) oldest_idle = older(oldest_idle, c);
    }
    if (oldest_handshaking) {
        close(*oldest_handshaking);
        return Standing::Handshaking;
    }
    if (oldest_stalled) {
        close(*oldest_stalled);
        return Standing::Stalled;
    }
    if (oldest_idle) {
        close(*oldest_idle);
        return Standing::Idle;
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
