#pragma once

#include <sys/epoll.h>

#include <asio/any_io_executor.hpp>
#include <asio/error_code.hpp>
#include <asio/io_context.hpp>  // also asio::detail::reactor, which needs it included first
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
// The set waits in Asio's reactor as a read operation of its own (asio/detail): its registration
// there is edge-triggered, and Asio's public async_wait() re-arms it with an epoll_ctl() on every
// wait, a fourth system call per request beside epoll_wait(), recv() and send(). An operation
// that is "done and exhausted" each time it is woken needs no re-arming: any socket of the set
// that becomes ready wakes the reactor again. Input that a watcher leaves unread makes no new
// edge, so a watcher says when it may have left some and the set is then looked at again.
//
// Every wake-up asks the set which sockets are ready and with what, even when only one is
// watched: a peer's FIN that came with its last request is consumed by no read that returns the
// request, and only the set's EPOLLRDHUP tells the watcher to read on to the end (a wake-up
// taken as "the one socket has input" left a third of such connections open, unread).
namespace mblab::transport {

class SocketPoller : public std::enable_shared_from_this<SocketPoller> {
  public:
    // What a watched socket is told: the epoll events (EPOLLIN, EPOLLOUT, EPOLLERR, ...).
    class Watcher {
      public:
        // True when the watcher may have left input unread (it read only part of what came, or
        // nothing): the poller looks at its socket again instead of waiting for new input.
        virtual bool on_ready(std::uint32_t events) = 0;

      protected:
        ~Watcher() = default;
    };

    // The poller must be used from the executor's thread only.
    static std::shared_ptr<SocketPoller> create(asio::any_io_executor executor);
    ~SocketPoller();

    // Watches `fd` for `events` (EPOLLERR and EPOLLHUP always come). The poller does not own
    // the watcher, which must remove() its descriptor before it is destroyed or closes it.
    // False with errno set if epoll refused the descriptor.
    bool add(int fd, Watcher& watcher, std::uint32_t events);
    // Changes the events watched; a no-op when they are the same.
    void modify(int fd, std::uint32_t events);
    // Stops watching `fd` (call before closing it). Safe from inside on_ready(): an event of
    // this batch for a removed descriptor is not delivered, not even to a watcher that adds the
    // same descriptor number again.
    void remove(int fd);

    std::size_t watched() const { return live_; }

  private:
    // A watched descriptor, by its number. epoll hands back the number and the slot's
    // generation, not a pointer: the dispatch loop then reads this compact table, not each
    // watcher's memory twice (with 1000 connections a watcher is seldom in cache), and an event
    // left in a batch for a descriptor removed since is recognised by its generation.
    struct Slot {
        Watcher* watcher = nullptr;
        std::uint32_t events = 0;
        std::uint32_t generation = 0;
    };
    class WaitOperation;
    explicit SocketPoller(asio::any_io_executor executor);
    Slot* find(int fd);
    void wait();
    void on_wait(const asio::error_code& ec);
    // Delivers the ready events. True when the set should be looked at again at once (a busy
    // batch, or input left unread).
    bool dispatch();
    void look_again();

    asio::any_io_executor executor_;
    asio::detail::reactor& reactor_;
    EpollSet epoll_;
    asio::detail::reactor::per_descriptor_data registration_ = nullptr;  // epoll_ in the reactor
    std::vector<Slot> slots_;                                            // by descriptor number
    std::vector<epoll_event> events_;
    std::unique_ptr<WaitOperation> spare_;  // the last wait, out of the reactor
    std::size_t live_ = 0;
    bool wait_pending_ = false;  // a WaitOperation is in the reactor
    bool look_pending_ = false;  // a look_again() is posted
};

}  // namespace mblab::transport
