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

bool ConnectionTable::close_oldest_idle() {
    // A linear scan: it runs only when the table is full, and a full table is rare.
    TrackedConnection* oldest = nullptr;
    for (auto* c = head_; c; c = c->next_) {
        if (c->closing_ || !c->idle()) continue;
        if (!oldest || c->last_activity() < oldest->last_activity()) oldest = c;
    }
    if (!oldest) return false;
    close(*oldest);
    return true;
}

void ConnectionTable::close_all() {
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
