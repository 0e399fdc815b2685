#pragma once

#include <sys/epoll.h>

#include <asio/any_io_executor.hpp>
#include <asio/posix/stream_descriptor.hpp>
#include <cstdint>
#include <memory>
#include <vector>

#include "transport/epoll_set.hpp"

// Readiness of many sockets through one epoll set of our own, level-triggered, that the
// io_context watches as a single descriptor. A socket Asio reads itself costs a second recv()
// per request: after each answer Asio tries to read again, speculatively, before waiting, and
// with a client that waits for the answer that read always finds nothing. Here a socket is read
// only when epoll says it has data, as a bare epoll loop does, and a whole batch of ready sockets
// costs one wake-up of the io_context. Timers, posts and every other descriptor stay with Asio.
//
// One client is the common case of a device. While only one socket is watched, and only for
// input, a wake-up can only be that socket's: it is told EPOLLIN without asking epoll, and a
// hang-up or an error shows in its read. That saves a system call on every request.
namespace mblab::transport {

class SocketPoller : public std::enable_shared_from_this<SocketPoller> {
  public:
    // What a watched socket is told: the epoll events (EPOLLIN, EPOLLOUT, EPOLLERR, ...).
    class Watcher {
      public:
        virtual void on_ready(std::uint32_t events) = 0;

      protected:
        ~Watcher() = default;
    };

    // The poller must be used from the executor's thread only.
    static std::shared_ptr<SocketPoller> create(asio::any_io_executor executor);
    ~SocketPoller();

    // Watches `fd` for `events` (EPOLLERR and EPOLLHUP always come). The poller does not own
    // the watcher, which must remove() its descriptor before closing it; a watcher that is gone
    // is not called. False with errno set if epoll refused the descriptor.
    bool add(int fd, const std::shared_ptr<Watcher>& watcher, std::uint32_t events);
    // Changes the events watched; a no-op when they are the same.
    void modify(int fd, std::uint32_t events);
    // Stops watching `fd` (call before closing it). Safe from inside on_ready(): an event of
    // this batch for a removed descriptor is not delivered.
    void remove(int fd);

    std::size_t watched() const { return live_; }

  private:
    struct Entry {
        std::uint32_t events = 0;
        std::weak_ptr<Watcher> watcher;
        bool removed = false;
    };
    explicit SocketPoller(asio::any_io_executor executor);
    Entry* find(int fd) const;
    // The only entry, when exactly one is watched.
    Entry* only_entry() const;
    void wait();
    void on_wait(const asio::error_code& ec);
    // Delivers the ready events; returns how many.
    int dispatch();

    EpollSet epoll_;                               // handed over: descriptor_ closes it
    asio::posix::stream_descriptor descriptor_;    // epoll_ as the io_context sees it
    std::vector<std::unique_ptr<Entry>> entries_;  // by descriptor number
    std::vector<std::unique_ptr<Entry>> removed_;  // entries an undelivered event may name
    std::vector<epoll_event> events_;
    std::size_t live_ = 0;
    Entry* sole_ = nullptr;  // the entry when live_ == 1
    bool waiting_ = false;
    bool dispatching_ = false;
};

}  // namespace mblab::transport
