#include "blocking_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <utility>

#include "support/hex.hpp"

namespace mblab::test {

BlockingClient::BlockingClient(std::uint16_t port, int receive_buffer) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) return;
    if (receive_buffer > 0) {
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    // Loopback connects complete or fail at once; no connect timeout needed.
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        ::close(fd_);
        fd_ = -1;
        return;
    }
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

BlockingClient::~BlockingClient() {
    if (fd_ >= 0) ::close(fd_);
}

BlockingClient::BlockingClient(BlockingClient&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), end_error_(other.end_error_) {}

BlockingClient& BlockingClient::operator=(BlockingClient&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        end_error_ = other.end_error_;
    }
    return *this;
}

bool BlockingClient::send(std::span<const std::uint8_t> bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        auto n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        sent += static_cast<std::size_t>(n);
    }
    return true;
}

bool BlockingClient::send_hex(std::string_view hex_bytes) {
    return send(hex(hex_bytes));
}

void BlockingClient::shutdown_send() {
    ::shutdown(fd_, SHUT_WR);
}

long BlockingClient::read_some(std::uint8_t* out, std::size_t count,
                               std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    int ready = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (ready == 0) return 0;
    if (ready < 0) return errno == EINTR ? 0 : -1;
    auto n = ::recv(fd_, out, count, 0);
    if (n > 0) return n;
    end_error_ = n == 0 ? 0 : errno;
    return -1;
}

std::vector<std::uint8_t> BlockingClient::read(std::size_t count,
                                               std::chrono::milliseconds timeout) {
    std::vector<std::uint8_t> out(count);
    std::size_t got = 0;
    auto deadline = std::chrono::steady_clock::now() + timeout;
    while (got < count) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) break;
        auto n = read_some(out.data() + got, count - got, left);
        if (n < 0) break;
        got += static_cast<std::size_t>(n);
    }
    out.resize(got);
    return out;
}

std::string BlockingClient::read_adu(std::chrono::milliseconds timeout) {
    auto deadline = std::chrono::steady_clock::now() + timeout;
    auto adu = read(7, timeout);
    if (adu.size() == 7) {
        std::size_t length = static_cast<std::size_t>(adu[4] << 8 | adu[5]);
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (length > 1 && left.count() > 0) {
            auto body = read(length - 1, left);
            adu.insert(adu.end(), body.begin(), body.end());
        }
    }
    return to_hex(adu);
}

std::string BlockingClient::transact(std::string_view request_hex,
                                     std::chrono::milliseconds timeout) {
    if (!send_hex(request_hex)) return "send failed";
    return read_adu(timeout);
}

bool BlockingClient::closed_by_peer(std::chrono::milliseconds timeout) {
    auto deadline = std::chrono::steady_clock::now() + timeout;
    std::uint8_t sink[512];
    for (;;) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) return false;
        auto n = read_some(sink, sizeof sink, left);
        if (n < 0) return true;
    }
}

}  // namespace mblab::test
