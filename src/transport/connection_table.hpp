#pragma once

#include <chrono>
#include <cstddef>

// The connections one listener has admitted, so that a full server can pick the one to give up
// ([TCPG] 4.2.1.1: close the oldest idle connection to admit a new one) and a stopping server
// can close them all.
namespace mblab::transport {

using Clock = std::chrono::steady_clock;

// What a full table may do with a connection to admit a newcomer.
enum class Standing : unsigned char {
    Busy,  // receiving a request at a normal pace or owed an answer by the device: kept
    Idle,  // no request being received, none being answered
    // Idle and has never carried a whole request: it has shown no use of its place, so it goes
    // before an idle one that has ([TCPG] 4.2.1.1 speaks of the oldest unused connection). By
    // age alone, connections opened faster than a client polls evict that client between polls.
    Unused,
    // Has completed no request and sent no answer for a while, yet is not idle: it trickles an
    // unfinished frame or leaves its answers unread. Such a client holds a place without using
    // it, so it goes before any idle one; otherwise a few hundred of them lock everyone out.
    Stalled,
    // Still in its TLS handshake: not yet authenticated, so it has shown no right to a place.
    // It goes before every other kind, or handshakes opened faster than they finish would
    // evict an authenticated session before each of its polls.
    Handshaking,
    // Its session is over: its last answer and its end went out, and it only reads what the
    // client still sends until the client ends too (a lingering close). It goes first: a session
    // still open is worth more than the reset its close may now cause.
    Ending,
};

class TrackedConnection {
  public:
    TrackedConnection() = default;
    TrackedConnection(const TrackedConnection&) = delete;
    TrackedConnection& operator=(const TrackedConnection&) = delete;

    virtual Standing standing(Clock::time_point now) const = 0;
    // The last complete request or answer; the oldest goes first.
    virtual Clock::time_point last_activity() const = 0;
    // Starts closing. It may call ConnectionTable::remove() for itself, and nothing else of the
    // table.
    virtual void close() = 0;

  protected:
    ~TrackedConnection() = default;

  private:
    friend class ConnectionTable;
    TrackedConnection* prev_ = nullptr;
    TrackedConnection* next_ = nullptr;
    bool closing_ = false;
};

class ConnectionTable {
  public:
    ConnectionTable() = default;
    ConnectionTable(const ConnectionTable&) = delete;
    ConnectionTable& operator=(const ConnectionTable&) = delete;

    void add(TrackedConnection& connection);
    // A connection leaves the table as it closes, not when its owner is destroyed: a session
    // that closed but still waits for its handlers to finish must not hold a place (a client
    // that reconnects at once would be refused). Removing one twice, or one never added, is
    // harmless.
    void remove(TrackedConnection& connection);
    std::size_t size() const { return size_; }

    // Closes the oldest connection still in its TLS handshake, or else the stalled one with the
    // oldest activity, or else the oldest unused one, or else the oldest idle one, to admit a
    // newcomer; returns which kind it closed, Busy when every connection is busy.
    Standing close_one_for_newcomer(Clock::time_point now);
    void close_all();

  private:
    void close(TrackedConnection& connection);

    TrackedConnection* head_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace mblab::transport
