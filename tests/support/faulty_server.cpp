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

bool FaultyServer::listen_on(std::uint16_t port) {
    listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    int one = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(port);
    socklen_t length = sizeof address;
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener_, 8) != 0 ||
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
        return false;
    }
    port_ = ntohs(address.sin_port);
    return true;
}

std::uint16_t FaultyServer::start() {
    if (!listen_on(0) || ::pipe(wake_) != 0) return 0;
    thread_ = std::thread([this] { serve(); });
    return port_;
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
        closed_by_rule_ = false;
        const bool died = serve_connection(fd);
        // Listening stops before the client sees the close, so that no connection of its can
        // slip into the backlog in between (and be reset rather than refused).
        if (died || (rule_.fault == Fault::SlowToReopen && closed_by_rule_)) {
            ::close(listener_);
            listener_ = -1;
        }
        ::close(fd);
        if (died) return;
        if (listener_ < 0) {
            pollfd wake{wake_[0], POLLIN, 0};
            if (::poll(&wake, 1, 600) != 0 || !listen_on(port_)) return;
        }
    }
}

bool FaultyServer::serve_connection(int fd) {
    std::vector<std::uint8_t> buffer;
    std::uint32_t requests = 0;  // on this connection
    // When the unfinished frame in the buffer began; the epoch while there is none.
    Clock::time_point partial_since{};
    while (true) {
        // Take every whole frame in the buffer; a reordering device answers them last first.
        std::vector<std::vector<std::uint8_t>> frames;
        while (buffer.size() >= 6) {
            const std::size_t length = static_cast<std::size_t>(buffer[4] << 8 | buffer[5]);
            if (length < 2) return false;  // not even a unit id and function code: hang up
            if (buffer.size() < 6 + length) break;
            const auto end = buffer.begin() + static_cast<long>(6 + length);
            frames.emplace_back(buffer.begin(), end);
            buffer.erase(buffer.begin(), end);
        }
        if (rule_.fault == Fault::ReorderAnswers) std::reverse(frames.begin(), frames.end());
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const auto& frame = frames[i];
            const bool modbus = frame[2] == 0 && frame[3] == 0;
            ++requests;
            if (rule_.fault == Fault::SilentAfter && requests > rule_.after) continue;
            if (rule_.fault == Fault::OnlyUnit255 && frame[6] != 0xFF) continue;
            if (modbus) answer(fd, frame.data(), frame.size(), i > 0);
            const bool closes = rule_.fault == Fault::CloseConnection ||
                                rule_.fault == Fault::Dies || rule_.fault == Fault::SlowToReopen;
            if (closes && modbus && (rule_.function == 0 || rule_.function == frame[7])) {
                closed_by_rule_ = true;
                return rule_.fault == Fault::Dies;
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
        if (ready < 0 || (fds[1].revents & POLLIN) != 0) return false;
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
        if (n <= 0) return false;
        buffer.insert(buffer.end(), chunk, chunk + n);
    }
}

void FaultyServer::answer(int fd, const std::uint8_t* frame, std::size_t size, bool queued) {
    std::array<std::uint8_t, 260> adu{};
    const std::uint8_t function = frame[7];
    const bool faulty = rule_.function == 0 || rule_.function == function;
    const Fault fault = faulty ? rule_.fault : Fault::None;
    device::RequestContext context{frame[6], device::Link::Tcp};
    const auto request = std::span(frame + 7, size - 7);
    auto pdu_out = std::span(adu).subspan(7, 253);
    device::Reply reply;
    if (fault == Fault::WriteNotApplied &&
        (function == 0x05 || function == 0x06 || function == 0x0F || function == 0x10)) {
        // The echo a device that wrote would give: the whole request for 05/06, address and
        // quantity for 0F/10.
        const std::size_t echo = function <= 0x06 ? request.size() : 5;
        std::copy(request.begin(), request.begin() + static_cast<long>(echo), pdu_out.begin());
        reply.size = echo;
    } else if ((fault == Fault::BusyWhenQueued && queued) || fault == Fault::IllegalFunction) {
        pdu_out[0] = static_cast<std::uint8_t>(function | 0x80);
        pdu_out[1] = fault == Fault::IllegalFunction ? 0x01 : 0x06;
        reply.size = 2;
    } else {
        reply = handler_.handle(context, request, pdu_out);
        if (reply.action != device::ReplyAction::Answer) return;
    }
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
        case Fault::Dies:
        case Fault::SlowToReopen:
            return;
        case Fault::LateAnswer:
            std::this_thread::sleep_for(std::chrono::milliseconds(150));
            break;
        case Fault::PadBitsSet:
            if (!exception && (function == 0x01 || function == 0x02)) {
                pdu[reply.size - 1] |= 0x80;  // bit 7 of the last byte: unused unless qty % 8 == 0
            }
            break;
        case Fault::DeviceIdPastPdu:
            // 2B 0E code level more next count | id length ...: the first length byte.
            if (!exception && function == 0x2B && reply.size > 8)
                pdu[8] = static_cast<std::uint8_t>(pdu[8] + 5);
            break;
        case Fault::DeviceIdEndless:
            if (!exception && function == 0x2B && reply.size > 6 && pdu[2] != 0x04) {
                pdu[4] = 0xFF;
                // The id after the last object sent: walk the objects.
                std::size_t at = 7;
                std::uint8_t last = 0;
                while (at + 1 < reply.size) {
                    last = pdu[at];
                    at += 2 + pdu[at + 1];
                }
                pdu[5] = static_cast<std::uint8_t>(last + 1);
            }
            break;
        case Fault::DeviceIdBasicLevel:
            if (!exception && function == 0x2B && reply.size > 3) pdu[3] = 0x81;
            break;
        case Fault::DataPastTheEnd:
            if (exception && function == 0x03 && pdu[1] == 0x02) {
                const std::uint16_t quantity =
                    static_cast<std::uint16_t>(request[3] << 8 | request[4]);
                pdu[0] = 0x03;
                pdu[1] = static_cast<std::uint8_t>(2 * quantity);
                std::fill(pdu + 2, pdu + 2 + 2 * quantity, 0);
                reply.size = 2 + 2U * quantity;
                length = reply.size + 1;
                adu[4] = static_cast<std::uint8_t>(length >> 8);
                adu[5] = static_cast<std::uint8_t>(length & 0xFF);
            }
            break;
        case Fault::None:
        case Fault::SplitAnswer:
        case Fault::ReorderAnswers:
        case Fault::BusyWhenQueued:
        case Fault::DuplicateAnswer:
        case Fault::UnsolicitedBytes:
        case Fault::WriteNotApplied:
        case Fault::IllegalFunction:
        case Fault::SilentAfter:
        case Fault::OnlyUnit255:
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
    if (fault == Fault::DuplicateAnswer) write_all(fd, adu.data(), total);
    if (fault == Fault::UnsolicitedBytes) {
        const std::array<std::uint8_t, 6> noise = {0xDE, 0xAD, 0xBE, 0xEF, 0x00, 0x01};
        write_all(fd, noise.data(), noise.size());
    }
}

}  // namespace mblab::test
