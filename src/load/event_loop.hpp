#pragma once

#include <sys/epoll.h>
#include <unistd.h>

#include <cstdint>

// epoll for the load generator. Asio would add a lock and a handler allocation per operation;
// the generator's ceiling is measured against a bare epoll client (bench/run_load_bench.sh), so
// it talks to epoll itself. Level-triggered: a connection reads once per wake-up and is woken
// again while bytes remain.
namespace mblab::load {

class EventLoop {
  public:
    EventLoop() : fd_(::epoll_create1(EPOLL_CLOEXEC)) {}
    ~EventLoop() {
        if (fd_ >= 0) ::close(fd_);
    }
    EventLoop(const EventLoop&) = delete;
    EventLoop& operator=(const EventLoop&) = delete;

    bool ok() const { return fd_ >= 0; }

    // `owner` comes back in epoll_event::data.ptr.
    void add(int fd, void* owner, bool want_write) {
        control(EPOLL_CTL_ADD, fd, owner, want_write);
    }
    void modify(int fd, void* owner, bool want_write) {
        control(EPOLL_CTL_MOD, fd, owner, want_write);
    }
    void remove(int fd) { ::epoll_ctl(fd_, EPOLL_CTL_DEL, fd, nullptr); }

    int wait(epoll_event* events, int capacity, int timeout_ms) {
        return ::epoll_wait(fd_, events, capacity, timeout_ms);
    }

  private:
    void control(int op, int fd, void* owner, bool want_write) {
        epoll_event event{};
        event.events = EPOLLIN | (want_write ? std::uint32_t{EPOLLOUT} : 0U);
        event.data.ptr = owner;
        ::epoll_ctl(fd_, op, fd, &event);
    }

    int fd_;
};

}  // namespace mblab::load
