#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "load/connection_port.hpp"
#include "transport/socket_channel.hpp"

namespace mblab::load {

namespace {

// Level-triggered: a connection reads once per wake-up and is woken again while bytes remain.
std::uint32_t interest(bool want_write) {
    return EPOLLIN | (want_write ? std::uint32_t{EPOLLOUT} : 0U);
}

class SocketPort final : public ConnectionPort {
  public:
    SocketPort(const LoadTarget& target, transport::EpollSet& epoll, void* owner)
        : target_(target), epoll_(epoll), owner_(owner) {}
    ~SocketPort() override {
        // A channel never taken (the owner went away mid-dial) would leave the descriptor open.
        if (fd_ >= 0 && !taken_) ::close(fd_);
    }

    Dial dial(int& error) override {
        const auto& address = target_.address;
        fd_ = ::socket(address.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
        if (fd_ < 0) {
            error = errno;
            return Dial::Failed;
        }
        taken_ = false;
        int one = 1;
        ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), target_.address_size) ==
            0) {
            return Dial::Open;
        }
        if (errno == EINPROGRESS) return Dial::Pending;
        error = errno;
        ::close(fd_);
        fd_ = -1;
        return Dial::Failed;
    }

    int dial_result() override {
        int code = 0;
        socklen_t size = sizeof code;
        if (::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &code, &size) != 0) code = errno;
        return code;
    }

    std::unique_ptr<transport::Channel> take_channel() override {
        taken_ = true;
        return std::make_unique<transport::SocketChannel>(fd_);
    }

    void watch(bool want_write) override {
        if (watched_) {
            epoll_.modify(fd_, owner_, interest(want_write));
        } else {
            watched_ = epoll_.add(fd_, owner_, interest(want_write));
        }
    }

    void release() override {
        if (watched_) epoll_.remove(fd_);
        watched_ = false;
        fd_ = -1;
    }

    bool connected() const override { return fd_ >= 0; }

  private:
    const LoadTarget& target_;
    transport::EpollSet& epoll_;
    void* owner_;
    int fd_ = -1;
    bool watched_ = false;
    bool taken_ = true;
};

}  // namespace

std::unique_ptr<ConnectionPort> SocketPorts::make(const LoadTarget& target, void* owner) {
    return std::make_unique<SocketPort>(target, epoll_, owner);
}

}  // namespace mblab::load
