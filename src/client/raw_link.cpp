#include "client/raw_link.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/core.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include "protocol/limits.hpp"

namespace mblab::client {

namespace {

using Clock = std::chrono::steady_clock;

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

int remaining_ms(Clock::time_point deadline) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    return left.count() < 0 ? 0 : static_cast<int>(left.count());
}

// Non-blocking connect bounded by the deadline; returns the socket or -1 with `error` set.
int connect_one(const addrinfo& info, Clock::time_point deadline, std::string& error) {
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

}  // namespace

protocol::Result<RawLink, LinkError> RawLink::connect(const Endpoint& endpoint,
                                                      std::chrono::milliseconds timeout,
                                                      LinkObserver* observer) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    std::string port = std::to_string(endpoint.port);
    if (int rc = ::getaddrinfo(endpoint.host.c_str(), port.c_str(), &hints, &found); rc != 0) {
        return LinkError{std::string("cannot resolve host: ") + ::gai_strerror(rc)};
    }
    const auto deadline = Clock::now() + timeout;
    std::string error = "no address";
    int fd = -1;
    for (addrinfo* info = found; info != nullptr && fd < 0; info = info->ai_next) {
        fd = connect_one(*info, deadline, error);
    }
    ::freeaddrinfo(found);
    if (fd < 0) return LinkError{error};

    // Blocking from here on: every wait is bounded by poll().
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    LinkAddresses addresses;
    sockaddr_storage local{};
    sockaddr_storage peer{};
    socklen_t local_len = sizeof local;
    socklen_t peer_len = sizeof peer;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_len) == 0 &&
        ::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &peer_len) == 0) {
        addresses.ipv6 = peer.ss_family == AF_INET6;
        describe(local, addresses.local_ip, addresses.local_port);
        describe(peer, addresses.peer_ip, addresses.peer_port);
    }
    RawLink link(fd, addresses, nullptr);
    if (endpoint.tls) {
        auto failed = link.handshake(*endpoint.tls, deadline);
        if (!failed.empty()) {
            return LinkError{failed, link.handshake_heard_};
        }
    }
    // Captures show Modbus, so they begin once TLS is up and see the plaintext.
    link.observer_ = observer;
    if (observer != nullptr) observer->on_open(addresses);
    return link;
}

std::string RawLink::handshake(const TlsSetup& setup, Clock::time_point deadline) {
    tls_ = std::make_unique<security::TlsChannel>(setup.context, security::TlsChannel::Side::Client,
                                                  setup.server_name);
    tls_->start();
    std::string error;
    std::array<std::uint8_t, 4096> chunk;
    while (tls_->state() == security::TlsChannel::State::Handshaking) {
        if (!send_cipher(error)) return "TLS handshake: " + error;
        pollfd pfd{fd_, POLLIN, 0};
        const int ready = ::poll(&pfd, 1, remaining_ms(deadline));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) return "TLS handshake timed out";
        const ssize_t n = ::recv(fd_, chunk.data(), chunk.size(), 0);
        handshake_heard_ = true;
        if (n <= 0) {
            // A server that refuses our certificate may close before its alert is read.
            return "TLS handshake: the server closed the connection" +
                   std::string(n == 0 ? "" : " (" + errno_text(errno) + ")");
        }
        tls_->received(std::span(chunk).first(static_cast<std::size_t>(n)));
        tls_->read({});
    }
    send_cipher(error);  // the client's last flight, or the alert that says why it failed
    if (tls_->state() != security::TlsChannel::State::Open) {
        return "TLS handshake: " + tls_->error();
    }
    return {};
}

bool RawLink::send_all(std::span<const std::uint8_t> bytes, std::string& error) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n < 0) {
            if (errno == EINTR) continue;
            error = errno_text(errno);
            return false;
        }
        sent += static_cast<std::size_t>(n);
    }
    return true;
}

bool RawLink::send_cipher(std::string& error) {
    const auto out = tls_->output();
    if (out.empty()) return true;
    const bool sent = send_all(out, error);
    tls_->sent(out.size());
    return sent;
}

RawLink::RawLink(int fd, const LinkAddresses& addresses, LinkObserver* observer)
    : fd_(fd), addresses_(addresses), observer_(observer) {}

RawLink::RawLink(RawLink&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      addresses_(other.addresses_),
      observer_(other.observer_),
      tls_(std::move(other.tls_)),
      alert_(std::move(other.alert_)),
      reader_(std::move(other.reader_)) {}

RawLink& RawLink::operator=(RawLink&& other) noexcept {
    if (this != &other) {
        close();
        fd_ = std::exchange(other.fd_, -1);
        addresses_ = other.addresses_;
        observer_ = other.observer_;
        tls_ = std::move(other.tls_);
        alert_ = std::move(other.alert_);
        reader_ = std::move(other.reader_);
    }
    return *this;
}

RawLink::~RawLink() {
    close();
}

void RawLink::close() {
    if (fd_ < 0) return;
    if (tls_ && tls_->state() == security::TlsChannel::State::Open) {
        // close_notify, so the server sees an orderly end rather than a truncation.
        tls_->close();
        std::string ignored;
        send_cipher(ignored);
    }
    drop(false);
}

void RawLink::drop(bool by_peer) {
    if (tls_) alert_ = tls_->alert_received();
    ::close(fd_);
    fd_ = -1;
    tls_.reset();
    reader_.reset();
    if (observer_ != nullptr) observer_->on_close(by_peer);
}

bool RawLink::renegotiate(LinkError& error) {
    if (!tls_ || tls_->state() != security::TlsChannel::State::Open) {
        error.message = "no open TLS session";
        return false;
    }
    if (!tls_->request_renegotiation()) {
        error.message = "TLS: this side could not start a renegotiation";
        return false;
    }
    if (!send_cipher(error.message)) {
        drop(true);
        return false;
    }
    return true;
}

bool RawLink::close_notify(std::chrono::milliseconds timeout, std::string& how) {
    if (!tls_ || tls_->state() != security::TlsChannel::State::Open) {
        how = "no open TLS session";
        return false;
    }
    tls_->close();
    std::string error;
    if (!send_cipher(error)) {
        how = "the connection was gone before close_notify could be sent: " + error;
        drop(true);
        return true;
    }
    const auto deadline = Clock::now() + timeout;
    std::array<std::uint8_t, 256> chunk;
    while (fd_ >= 0) {
        std::string detail;
        std::size_t got = 0;
        const Fill fill = read_some(deadline, detail, chunk, got);
        if (fill == Fill::Timeout) {
            how = fmt::format("the server kept the connection open {} ms after close_notify",
                              timeout.count());
            return false;
        }
        if (fill == Fill::Closed) {
            how = tls_ && tls_->state() == security::TlsChannel::State::Closed
                      ? "the server answered with its close_notify"
                      : "the server closed the connection";
            drop(true);
            return true;
        }
    }
    how = "connection closed";
    return true;
}

bool RawLink::send(std::span<const std::uint8_t> bytes, LinkError& error) {
    if (fd_ < 0) {
        error.message = "connection closed";
        return false;
    }
    const bool sent =
        tls_ ? tls_->write(bytes) && send_cipher(error.message) : send_all(bytes, error.message);
    if (!sent) {
        if (error.message.empty()) error.message = "TLS: " + tls_->error();
        drop(true);
        return false;
    }
    if (observer_ != nullptr) observer_->on_sent(bytes);
    return true;
}

std::size_t RawLink::send_for(std::span<const std::uint8_t> bytes,
                              std::chrono::milliseconds timeout, LinkError& error) {
    if (fd_ < 0) {
        error.message = "connection closed";
        return 0;
    }
    const auto deadline = Clock::now() + timeout;
    // Over TLS the channel takes the plaintext whole, and its records go out as the peer takes
    // them; what is left waits in the channel for the next write.
    if (tls_ && !tls_->write(bytes)) {
        error.message = "TLS: " + tls_->error();
        drop(true);
        return 0;
    }
    auto wire = [&] { return tls_ ? tls_->output() : bytes; };
    std::size_t sent = 0;
    while (sent < wire().size()) {
        pollfd pfd{fd_, POLLOUT, 0};
        const int ready = ::poll(&pfd, 1, remaining_ms(deadline));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) break;
        const auto pending = wire().subspan(tls_ ? 0 : sent);
        const ssize_t n = ::send(fd_, pending.data(), pending.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
            error.message = errno_text(errno);
            drop(true);
            break;
        }
        if (tls_) {
            tls_->sent(static_cast<std::size_t>(n));
        } else {
            sent += static_cast<std::size_t>(n);
        }
    }
    const std::size_t taken = tls_ ? bytes.size() : sent;
    if (observer_ != nullptr && taken > 0) observer_->on_sent(bytes.first(taken));
    return taken;
}

bool RawLink::vanish() {
    if (fd_ < 0) return false;
    const int on = 1;
    if (::setsockopt(fd_, IPPROTO_TCP, TCP_REPAIR, &on, sizeof on) != 0) return false;
    // In repair mode close() frees the socket silently; the capture shows no close either.
    ::close(fd_);
    fd_ = -1;
    tls_.reset();
    reader_.reset();
    return true;
}

bool RawLink::can_vanish() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return false;
    const int on = 1;
    const bool allowed = ::setsockopt(fd, IPPROTO_TCP, TCP_REPAIR, &on, sizeof on) == 0;
    ::close(fd);
    return allowed;
}

RawLink::Fill RawLink::read_some(Clock::time_point deadline, std::string& detail,
                                 std::span<std::uint8_t> chunk, std::size_t& got) {
    got = 0;
    if (fd_ < 0) {
        detail = "connection closed";
        return Fill::Closed;
    }
    // Records already decrypted need no wait for the socket.
    if (!(tls_ && tls_->has_input())) {
        pollfd pfd{fd_, POLLIN, 0};
        int ready = ::poll(&pfd, 1, remaining_ms(deadline));
        if (ready < 0 && errno == EINTR) return Fill::Data;  // caller loops, re-checks the deadline
        if (ready <= 0) return Fill::Timeout;
    }
    const Fill fill = read_plain(detail, chunk, got);
    if (got > 0 && observer_ != nullptr) observer_->on_received(chunk.first(got));
    return fill;
}

RawLink::Fill RawLink::read_plain(std::string& detail, std::span<std::uint8_t> chunk,
                                  std::size_t& got) {
    if (!tls_) {
        ssize_t n = ::recv(fd_, chunk.data(), chunk.size(), 0);
        if (n <= 0) {
            detail = n == 0 ? "connection closed by peer" : errno_text(errno);
            return Fill::Closed;
        }
        got = static_cast<std::size_t>(n);
        return Fill::Data;
    }
    got = tls_->read(chunk);
    if (got > 0) return Fill::Data;
    using State = security::TlsChannel::State;
    if (tls_->state() == State::Open) {
        std::array<std::uint8_t, 4096> cipher;
        ssize_t n = ::recv(fd_, cipher.data(), cipher.size(), MSG_DONTWAIT);
        if (n == 0) {
            detail = "connection closed by peer (without TLS close_notify)";
            return Fill::Closed;
        }
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return Fill::Data;
            detail = errno_text(errno);
            return Fill::Closed;
        }
        tls_->received(std::span(cipher).first(static_cast<std::size_t>(n)));
        got = tls_->read(chunk);
        std::string ignored;
        send_cipher(ignored);  // a key update's answer, a close_notify's
        if (got > 0 || tls_->state() == State::Open) return Fill::Data;
    }
    detail = tls_->state() == State::Closed ? "the server closed the TLS session (close_notify)"
                                            : "TLS: " + tls_->error();
    return Fill::Closed;
}

RawLink::Fill RawLink::fill(Clock::time_point deadline, std::string& detail) {
    std::array<std::uint8_t, 1024> chunk;
    std::size_t got = 0;
    const Fill fill = read_some(deadline, detail, chunk, got);
    reader_.add(std::span(chunk).first(got));
    return fill;
}

std::optional<Received> RawLink::wait(Clock::time_point deadline) {
    std::string detail;
    switch (fill(deadline, detail)) {
        case Fill::Data:
            return std::nullopt;
        case Fill::Timeout:
            return reader_.take(ReceiveStatus::Timeout);
        case Fill::Closed:
            break;
    }
    Received out = reader_.take(ReceiveStatus::Closed, detail);
    if (fd_ >= 0) drop(true);
    return out;
}

Received RawLink::receive_frame(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
        if (auto frame = reader_.next()) return std::move(*frame);
        if (auto done = wait(deadline)) return std::move(*done);
    }
}

Received RawLink::next_frame(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
        if (auto frame = reader_.next()) return std::move(*frame);
        std::string detail;
        switch (fill(deadline, detail)) {
            case Fill::Data:
                break;
            case Fill::Timeout:
                return Received(ReceiveStatus::Timeout);
            case Fill::Closed: {
                Received out = reader_.take(ReceiveStatus::Closed, detail);
                if (fd_ >= 0) drop(true);
                return out;
            }
        }
    }
}

Received RawLink::receive_any(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    // Bytes are taken as they come, not as frames; whatever the reader held comes first. A
    // device that floods must not make the tester allocate as it reads: the bytes past the
    // first kKeptUnasked are only counted.
    Received out = reader_.take(ReceiveStatus::Timeout);
    if (out.bytes.size() > kKeptUnasked) {
        out.discarded = out.bytes.size() - kKeptUnasked;
        out.bytes.resize(kKeptUnasked);
    }
    out.bytes.reserve(kKeptUnasked);
    std::array<std::uint8_t, 1024> chunk;
    while (true) {
        std::size_t got = 0;
        const Fill fill = read_some(deadline, out.detail, chunk, got);
        const std::size_t taken = std::min(got, kKeptUnasked - out.bytes.size());
        out.bytes.insert(out.bytes.end(), chunk.begin(), chunk.begin() + static_cast<long>(taken));
        out.discarded += got - taken;
        if (fill == Fill::Closed) {
            out.status = ReceiveStatus::Closed;
            if (fd_ >= 0) drop(true);
            return out;
        }
        // A device that never stops sending must not keep the tester here past the deadline.
        if (fill == Fill::Timeout || Clock::now() >= deadline) return out;
    }
}

}  // namespace mblab::client
