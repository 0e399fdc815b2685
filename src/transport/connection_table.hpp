#pragma once

#include <chrono>
#include <cstddef>

// The connections one listener has admitted, so that a full server can pick the one to give up
// ([TCPG] 4.2.1.1: close the oldest idle connection to admit a new one) and a stopping server
// can close them all.
namespace mblab::transport {

using Clock = std::chrono::steady_clock;

class TrackedConnection {
  public:
    TrackedConnection() = default;
    TrackedConnection(const TrackedConnection&) = delete;
    TrackedConnection& operator=(const TrackedConnection&) = delete;

    // Idle: no request being received, none being answered. Only idle connections are evicted.
    virtual bool idle() const = 0;
    // The last complete request or answer; the oldest idle connection goes first.
    virtual Clock::time_point last_activity() const = 0;
    // Starts closing; must not reenter the table (removal happens when the owner ends).
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
    void remove(TrackedConnection& connection);
    // Connections admitted and not yet removed, closing ones included.
    std::size_t size() const { return size_; }

    // Closes the idle connection with the oldest activity; false when none is idle.
    bool close_oldest_idle();
    void close_all();

  private:
    void close(TrackedConnection& connection);

    TrackedConnection* head_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace mblab::transport
