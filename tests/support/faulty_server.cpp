#include "support/faulty_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <vector>

namespace mblab::test {

namespace {

using Clock = std::chrono::steady_clock;

void write_all(int fd, const std::uint8_t* bytes, std::size_t size) {
    while (size > 0) {
        ssize_t n = ::send(fd, bytes, size, MSG_NOSIGNAL);
        if (n <= 0) return;
        bytes += n;
        size -= static_cast<std::size_t>(n);
    }
}

bool is_echo(std::uint8_t function) {
    return function == 0x05 || function == 0x06 || function == 0x08 || function == 0x0F ||
           function == 0x10;
}

bool is_read(std::uint8_t function) {
    return function >= 0x01 && function <= 0x04;
}

}  // namespace

FaultyServer::FaultyServer(device::RequestHandler& handler, FaultRule rule)
    : handler_(handler), rule_(rule) {}

FaultyServer::~FaultyServer() {
    stop();
}

std::uint16_t FaultyServer::start() {
    listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    int one = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener_, 8) != 0 ||
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) != 0 ||
        ::pipe(wake_) != 0) {
        return 0;
    }
    thread_ = std::thread([this] { serve(); });
    return ntohs(address.sin_port);
}

void FaultyServer::stop() {
    if (thread_.joinable()) {
        const std::uint8_t byte = 1;
        [[maybe_unused]] auto ignored = ::write(wake_[1], &byte, 1);
        thread_.join();
    }
    for (int* fd : {&listener_, &wake_[0], &wake_[1]}) {
        if (*fd >= 0) ::close(*fd);
        *fd = -1;
    }
}

void FaultyServer::serve() {
    while (true) {
        std::array<pollfd, 2> fds{pollfd{listener_, POLLIN, 0}, pollfd{wake_[0], POLLIN, 0}};
        if (::poll(fds.data(), fds.size(), -1) < 0 || (fds[1].revents & POLLIN) != 0) return;
        int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) continue;
        int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        serve_connection(fd);
        ::close(fd);
    }
}

void FaultyServer::serve_connection(int fd) {
    std::vector<std::uint8_t> buffer;
    // When the unfinished frame in the buffer began; the epoch while there is none.
    Clock::time_point partial_since{};
    while (true) {
        // Take every whole frame in the buffer; a reordering device answers them last first.
        std::vector<std::vector<std::uint8_t>> frames;
        while (buffer.size() >= 6) {
            const std::size_t length = static_cast<std::size_t>(buffer[4] << 8 | buffer[5]);
            if (length < 2) return;  // not even a unit id and function code: hang up
            if (buffer.size() < 6 + length) break;
            const auto end = buffer.begin() + static_cast<long>(6 + length);
            frames.emplace_back(buffer.begin(), end);
            buffer.erase(buffer.begin(), end);
        }
        if (rule_.fault == Fault::ReorderAnswers) std::reverse(frames.begin(), frames.end());
        for (const auto& frame : frames) {
            const bool modbus = frame[2] == 0 && frame[3] == 0;
            if (modbus) answer(fd, frame.data(), frame.size());
            if (rule_.fault == Fault::CloseConnection && modbus &&
                (rule_.function == 0 || rule_.function == frame[7])) {
                return;
            }
        }
        if (buffer.empty()) {
            partial_since = {};
        } else if (partial_since == Clock::time_point{}) {
            partial_since = Clock::now();
        }
        int wait = -1;
        if (partial_since != Clock::time_point{}) {
            auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                partial_since + kPartialFrameWait - Clock::now());
            wait = static_cast<int>(std::max<long>(0, left.count()));
        }
        std::array<pollfd, 2> fds{pollfd{fd, POLLIN, 0}, pollfd{wake_[0], POLLIN, 0}};
        int ready = ::poll(fds.data(), fds.size(), wait);
        if (ready < 0 || (fds[1].revents & POLLIN) != 0) return;
        if (ready == 0) {
            // 9.1.3: a frame whose length promised more than came is answered with 03.
            if (buffer.size() >= 8) {
                const std::array<std::uint8_t, 9> refusal = {
                    buffer[0], buffer[1], 0,         0,
                    0,         3,         buffer[6], static_cast<std::uint8_t>(buffer[7] | 0x80),
                    0x03};
                write_all(fd, refusal.data(), refusal.size());
            }
            buffer.clear();
            continue;
        }
        std::uint8_t chunk[1024];
        ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
        if (n <= 0) return;
        buffer.insert(buffer.end(), chunk, chunk + n);
    }
}

void FaultyServer::answer(int fd, const std::uint8_t* frame, std::size_t size) {
    std::array<std::uint8_t, 260> adu{};
    device::RequestContext context{frame[6], device::Link::Tcp};
    auto reply =
        handler_.handle(context, std::span(frame + 7, size - 7), std::span(adu).subspan(7, 253));
    if (reply.action != device::ReplyAction::Answer) return;
    const std::uint8_t function = frame[7];
    const bool faulty = rule_.function == 0 || rule_.function == function;
    const Fault fault = faulty ? rule_.fault : Fault::None;
    std::size_t length = reply.size + 1;
    std::copy(frame, frame + 2, adu.begin());
    adu[4] = static_cast<std::uint8_t>(length >> 8);
    adu[5] = static_cast<std::uint8_t>(length & 0xFF);
    adu[6] = frame[6];
    std::uint8_t* pdu = adu.data() + 7;
    const bool exception = (pdu[0] & 0x80) != 0;
    switch (fault) {
        case Fault::WrongTransactionId:
            adu[1] = static_cast<std::uint8_t>(adu[1] + 1);
            break;
        case Fault::WrongLength:
            adu[5] = static_cast<std::uint8_t>(adu[5] - 1);
            break;
        case Fault::WrongUnitId:
            adu[6] = static_cast<std::uint8_t>(adu[6] + 1);
            break;
        case Fault::WrongByteCount:
            if (!exception && is_read(function)) pdu[1] = static_cast<std::uint8_t>(pdu[1] + 1);
            break;
        case Fault::WrongExceptionCode:
            if (exception) pdu[1] = pdu[1] == 0x04 ? 0x01 : 0x04;
            break;
        case Fault::WrongEcho:
            if (!exception && is_echo(function)) pdu[reply.size - 1] ^= 0x01;
            break;
        case Fault::NoAnswer:
        case Fault::CloseConnection:
            return;
        case Fault::LateAnswer:
            std::this_thread::sleep_for(std::chrono::milliseconds(150));
            break;
        case Fault::None:
        case Fault::SplitAnswer:
        case Fault::ReorderAnswers:
            break;
    }
    const std::size_t total = 7 + reply.size;
    if (fault == Fault::SplitAnswer && total >= 6) {
        // Cut inside the header and inside the PDU, so both reassemblies are exercised.
        const std::size_t cuts[] = {0, 3, 8 < total ? 8 : total - 1, total};
        for (std::size_t i = 0; i + 1 < std::size(cuts); ++i) {
            write_all(fd, adu.data() + cuts[i], cuts[i + 1] - cuts[i]);
            if (i + 2 < std::size(cuts)) std::this_thread::sleep_for(std::chrono::milliseconds(30));
        }
        return;
    }
    write_all(fd, adu.data(), total);
}

}  // namespace mblab::test
