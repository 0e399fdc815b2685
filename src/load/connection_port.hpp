#pragma once

#include <cstdint>
#include <memory>

#include "load/plan.hpp"
#include "transport/channel.hpp"
#include "transport/epoll_set.hpp"

// Where a load connection's bytes go and how it learns it may move them: a non-blocking TCP
// socket in its worker's epoll set, or, in tests, one end of an in-memory pair whose readiness
// the test reports by calling LoadConnection::on_event itself. The connection keeps every
// decision (its window, timeouts, reconnects, TLS); a port only opens, watches and lets go.
namespace mblab::load {

class ConnectionPort {
  public:
    enum class Dial : std::uint8_t {
        Open,     // connected at once
        Pending,  // on_event with EPOLLOUT says it ended; dial_result() says how
        Failed,   // `error` holds errno
    };

    virtual ~ConnectionPort() = default;

    virtual Dial dial(int& error) = 0;
    // After Pending: 0 once connected, else the errno of the failure.
    virtual int dial_result() = 0;
    // The connected channel, once per dial that did not fail.
    virtual std::unique_ptr<transport::Channel> take_channel() = 0;
    // Wake the owner for input, and for room to write when `want_write`.
    virtual void watch(bool want_write) = 0;
    // Stops watching; the channel, dropped after this, closes the connection.
    virtual void release() = 0;
    // Between a dial that did not fail and release().
    virtual bool connected() const = 0;
};

class ConnectionPorts {
  public:
    virtual ~ConnectionPorts() = default;
    // `owner` is what the readiness loop hands events back to.
    virtual std::unique_ptr<ConnectionPort> make(const LoadTarget& target, void* owner) = 0;
};

// TCP sockets in one worker's epoll set.
class SocketPorts final : public ConnectionPorts {
  public:
    explicit SocketPorts(transport::EpollSet& epoll) : epoll_(epoll) {}
    std::unique_ptr<ConnectionPort> make(const LoadTarget& target, void* owner) override;

  private:
    transport::EpollSet& epoll_;
};

}  // namespace mblab::load
