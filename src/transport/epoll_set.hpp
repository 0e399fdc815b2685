#pragma once

#include <sys/epoll.h>
#include <unistd.h>

#include <cstdint>
#include <span>

// The one epoll wrapper of the tree. The server's SocketPoller watches a set through its
// io_context; the load generator's workers wait on theirs directly from their own threads, since
// Asio would add a lock and a handler allocation per operation and the generator's ceiling is
// measured against a bare epoll client (bench/run_load_bench.sh). Inline, so that either costs
// exactly the system calls it makes. Level-triggered: whoever is told a socket is readable may
// read it once and is told again while bytes remain.
namespace mblab::transport {

class EpollSet {
  public:
    // ok() is false, with errno set, when the kernel refuses a new set.
    EpollSet() : fd_(::epoll_create1(EPOLL_CLOEXEC)) {}
    ~EpollSet() {
        if (fd_ >= 0) ::close(fd_);
    }
    EpollSet(const EpollSet&) = delete;
    EpollSet& operator=(const EpollSet&) = delete;

    bool ok() const { return fd_ >= 0; }
    int fd() const { return fd_; }

    // `owner` comes back in epoll_event::data.ptr, a `key` in data.u64. False with errno set if
    // epoll refused.
    bool add(int fd, void* owner, std::uint32_t events) {
        return control(EPOLL_CTL_ADD, fd, {.ptr = owner}, events);
    }
    bool add(int fd, std::uint64_t key, std::uint32_t events) {
        return control(EPOLL_CTL_ADD, fd, {.u64 = key}, events);
    }
    bool modify(int fd, void* owner, std::uint32_t events) {
        return control(EPOLL_CTL_MOD, fd, {.ptr = owner}, events);
    }
    bool modify(int fd, std::uint64_t key, std::uint32_t events) {
        return control(EPOLL_CTL_MOD, fd, {.u64 = key}, events);
    }
    void remove(int fd) { ::epoll_ctl(fd_, EPOLL_CTL_DEL, fd, nullptr); }

    // Fills the front of `batch`; returns how many were filled, or -1 with errno set.
    int wait(std::span<epoll_event> batch, int timeout_ms) {
        return ::epoll_wait(fd_, batch.data(), static_cast<int>(batch.size()), timeout_ms);
    }

  private:
    bool control(int op, int fd, epoll_data_t data, std::uint32_t events) {
        epoll_event event{};
        event.events = events;
        event.data = data;
        return ::epoll_ctl(fd_, op, fd, &event) == 0;
    }

    int fd_;
};

}  // namespace mblab::transport
