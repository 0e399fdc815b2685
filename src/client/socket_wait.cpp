#include "client/socket_wait.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mblab::client {

std::string errno_text(int code) {
    switch (code) {
        case ECONNREFUSED:
            return "connection refused";
        case ETIMEDOUT:
            return "connection timed out";
        case EHOSTUNREACH:
            return "host unreachable";
        case ENETUNREACH:
            return "network unreachable";
        case ECONNRESET:
            return "connection reset by peer";
        case EPIPE:
            return "connection closed by peer";
        default:
            return std::strerror(code);
    }
}

int remaining_ms(SteadyClock::time_point deadline) {
    if (deadline == SteadyClock::time_point::max()) return -1;
    auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
    return left.count() < 0 ? 0 : static_cast<int>(left.count());
}

bool wait_ready(int fd, short events, SteadyClock::time_point deadline) {
    pollfd pfd{fd, events, 0};
    const int ready = ::poll(&pfd, 1, remaining_ms(deadline));
    return ready > 0 || (ready < 0 && errno == EINTR);
}

int connect_one(const addrinfo& info, SteadyClock::time_point deadline, std::string& error) {
    int fd =
        ::socket(info.ai_family, info.ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, info.ai_protocol);
    if (fd < 0) {
        error = errno_text(errno);
        return -1;
    }
    if (::connect(fd, info.ai_addr, info.ai_addrlen) != 0 && errno != EINPROGRESS) {
        error = errno_text(errno);
        ::close(fd);
        return -1;
    }
    pollfd pfd{fd, POLLOUT, 0};
    int ready = ::poll(&pfd, 1, remaining_ms(deadline));
    int so_error = 0;
    socklen_t len = sizeof so_error;
    if (ready <= 0) {
        error = ready == 0 ? "connection timed out" : errno_text(errno);
    } else if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &so_error, &len) != 0 || so_error != 0) {
        error = errno_text(so_error != 0 ? so_error : errno);
    } else {
        return fd;
    }
    ::close(fd);
    return -1;
}

void describe(const sockaddr_storage& address, std::array<std::uint8_t, 16>& ip,
              std::uint16_t& port) {
    if (address.ss_family == AF_INET) {
        const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
        std::memcpy(ip.data(), &v4->sin_addr, 4);
        port = ntohs(v4->sin_port);
    } else if (address.ss_family == AF_INET6) {
        const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
        std::memcpy(ip.data(), &v6->sin6_addr, 16);
        port = ntohs(v6->sin6_port);
    }
}

}  // namespace mblab::client
