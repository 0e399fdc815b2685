#include "support/malicious_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>

namespace mblab::test {

namespace {

// A request that never completes is given up after this long, so a test cannot hang here.
constexpr int kReadWaitMs = 5000;
constexpr std::size_t kMbapHeader = 7;

bool send_all(int fd, std::span<const std::uint8_t> bytes) {
    while (!bytes.empty()) {
        const ssize_t sent = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
        if (sent <= 0) return false;
        bytes = bytes.subspan(static_cast<std::size_t>(sent));
    }
    return true;
}

}  // namespace

std::vector<std::uint8_t> mbap_frame(std::uint16_t transaction_id, std::uint16_t protocol_id,
                                     std::uint16_t length, std::uint8_t unit,
                                     std::span<const std::uint8_t> pdu) {
    std::vector<std::uint8_t> frame;
    frame.reserve(7 + pdu.size());
    for (std::uint16_t field : {transaction_id, protocol_id, length}) {
        frame.push_back(static_cast<std::uint8_t>(field >> 8));
        frame.push_back(static_cast<std::uint8_t>(field & 0xFF));
    }
    frame.push_back(unit);
    for (auto byte : pdu)
        frame.push_back(byte);
    return frame;
}

std::vector<std::uint8_t> mbap_answer(std::span<const std::uint8_t> request,
                                      std::span<const std::uint8_t> pdu) {
    const auto transaction_id = static_cast<std::uint16_t>((request[0] << 8) | request[1]);
    return mbap_frame(transaction_id, 0, static_cast<std::uint16_t>(pdu.size() + 1), request[6],
                      pdu);
}

MaliciousServer::MaliciousServer(AnswerScript script) : script_(std::move(script)) {}

MaliciousServer::~MaliciousServer() {
    stop();
}

std::uint16_t MaliciousServer::start() {
    if (::pipe(stop_pipe_) != 0) return 0;
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in bound{};
    bound.sin_family = AF_INET;
    bound.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof bound;
    const bool listening =
        listen_fd_ >= 0 && ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&bound), size) == 0 &&
        ::listen(listen_fd_, 4) == 0 &&
        ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &size) == 0;
    if (!listening) return 0;
    thread_ = std::thread([this] { run(); });
    return ntohs(bound.sin_port);
}

void MaliciousServer::stop() {
    if (thread_.joinable()) {
        ::close(stop_pipe_[1]);  // wakes every poll: the read end reports end of file
        stop_pipe_[1] = -1;
        thread_.join();
    }
    for (int fd : {listen_fd_, stop_pipe_[0], stop_pipe_[1]}) {
        if (fd >= 0) ::close(fd);
    }
    listen_fd_ = stop_pipe_[0] = stop_pipe_[1] = -1;
}

bool MaliciousServer::readable(int fd) {
    std::array<pollfd, 2> watched = {pollfd{fd, POLLIN, 0}, pollfd{stop_pipe_[0], POLLIN, 0}};
    if (::poll(watched.data(), watched.size(), kReadWaitMs) <= 0) return false;
    return watched[1].revents == 0;
}

bool MaliciousServer::read_exact(int fd, std::uint8_t* out, std::size_t size) {
    while (size > 0) {
        if (!readable(fd)) return false;
        const ssize_t got = ::recv(fd, out, size, 0);
        if (got <= 0) return false;
        out += got;
        size -= static_cast<std::size_t>(got);
    }
    return true;
}

void MaliciousServer::run() {
    while (readable(listen_fd_)) {
        const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) continue;
        converse(fd);
        ::close(fd);
    }
}

void MaliciousServer::converse(int fd) {
    std::array<std::uint8_t, 300> request{};
    while (read_exact(fd, request.data(), kMbapHeader)) {
        const std::size_t length = (request[4] << 8) | request[5];
        if (length < 1 || kMbapHeader - 1 + length > request.size()) return;
        if (!read_exact(fd, request.data() + kMbapHeader, length - 1)) return;
        const Answer answer =
            script_(std::span(request).first(kMbapHeader - 1 + length), requests_.fetch_add(1));
        if (answer.delay.count() > 0) {
            pollfd stopping{stop_pipe_[0], POLLIN, 0};
            if (::poll(&stopping, 1, static_cast<int>(answer.delay.count())) != 0) return;
        }
        if (!send_all(fd, answer.bytes) || answer.close) return;
    }
}

}  // namespace mblab::test
