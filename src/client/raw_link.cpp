#include "client/raw_link.hpp"

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
#include <optional>
#include <string>
#include <utility>

#include "client/socket_wait.hpp"
#include "transport/socket_channel.hpp"

namespace mblab::client {

namespace {

using Clock = std::chrono::steady_clock;
using Status = transport::Io::Status;
using TlsState = security::TlsChannel::State;

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
    auto stream = std::make_unique<transport::TlsStream>(
        std::move(channel_), setup.context, transport::TlsStream::Side::Client, setup.server_name);
    tls_ = stream.get();
    channel_ = std::move(stream);
    auto io = tls_->start();
    while (io.status != Status::Failed && tls_->handshaking()) {
        io = tls_->handshake();
        if (io.status != Status::WouldBlock) break;
        const short events = POLLIN | (tls_->wants_write() ? POLLOUT : 0);
        if (!wait_ready(fd_, events, deadline)) return "TLS handshake timed out";
    }
    handshake_heard_ = tls_->heard_peer();
    switch (io.status) {
        case Status::Done:
            return {};
        case Status::WouldBlock:
            return "TLS handshake timed out";
        case Status::EndOfInput:
            // A server that refuses our certificate may close before its alert is read.
            return "TLS handshake: the server closed the connection";
        case Status::Failed:
            break;
    }
    if (io.code == 0) return "TLS handshake: " + tls_->error();
    if (handshake_heard_) {
        return "TLS handshake: the server closed the connection (" + errno_text(io.code) + ")";
    }
    return "TLS handshake: " + errno_text(io.code);
}

bool RawLink::send_all(std::span<const std::uint8_t> bytes, std::string& error) {
    std::size_t sent = 0;
    for (;;) {
        transport::Io io;
        if (sent < bytes.size()) {
            io = channel_->write(bytes.subspan(sent));
            sent += io.bytes;
        } else if (channel_->wants_write()) {
            io = channel_->flush();  // TLS records held back
        } else {
            return true;
        }
        if (io.status == Status::Failed) {
            error = io.code != 0 ? errno_text(io.code) : "TLS: " + channel_->error();
            return false;
        }
        if (io.bytes == 0) wait_ready(fd_, POLLOUT, Clock::time_point::max());
    }
}

RawLink::RawLink(int fd, const LinkAddresses& addresses, LinkObserver* observer)
    : fd_(fd),
      channel_(std::make_unique<transport::SocketChannel>(fd)),
      addresses_(addresses),
      observer_(observer) {}

RawLink::RawLink(RawLink&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      channel_(std::move(other.channel_)),
      tls_(std::exchange(other.tls_, nullptr)),
      addresses_(other.addresses_),
      observer_(other.observer_),
      alert_(std::move(other.alert_)),
      reader_(std::move(other.reader_)) {}

RawLink& RawLink::operator=(RawLink&& other) noexcept {
    if (this != &other) {
        close();
        fd_ = std::exchange(other.fd_, -1);
        channel_ = std::move(other.channel_);
        tls_ = std::exchange(other.tls_, nullptr);
        addresses_ = other.addresses_;
        observer_ = other.observer_;
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
    if (tls_ && tls_->session().state() == TlsState::Open) {
        // close_notify, so the server sees an orderly end rather than a truncation.
        tls_->close_notify();
        std::string ignored;
        send_all({}, ignored);
    }
    drop(false);
}

void RawLink::drop(bool by_peer) {
    if (tls_) alert_ = tls_->session().alert_received();
    tls_ = nullptr;
    channel_.reset();  // closes the socket
    fd_ = -1;
    reader_.reset();
    if (observer_ != nullptr) observer_->on_close(by_peer);
}

bool RawLink::renegotiate(LinkError& error) {
    if (!tls_ || tls_->session().state() != TlsState::Open) {
        error.message = "no open TLS session";
        return false;
    }
    if (!tls_->session().request_renegotiation()) {
        error.message = "TLS: this side could not start a renegotiation";
        return false;
    }
    if (!send_all({}, error.message)) {
        drop(true);
        return false;
    }
    return true;
}

bool RawLink::close_notify(std::chrono::milliseconds timeout, std::string& how) {
    if (!tls_ || tls_->session().state() != TlsState::Open) {
        how = "no open TLS session";
        return false;
    }
    tls_->close_notify();
    std::string error;
    if (!send_all({}, error)) {
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
            how = tls_ && tls_->session().state() == TlsState::Closed
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
    if (!send_all(bytes, error.message)) {
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
    std::size_t taken = 0;
    while (taken < bytes.size() || channel_->wants_write()) {
        if (!wait_ready(fd_, POLLOUT, deadline)) break;
        const auto io =
            taken < bytes.size() ? channel_->write(bytes.subspan(taken)) : channel_->flush();
        if (io.status == Status::Failed) {
            error.message = io.code != 0 ? errno_text(io.code) : "TLS: " + channel_->error();
            drop(true);
            break;
        }
        if (taken < bytes.size()) taken += io.bytes;
    }
    if (observer_ != nullptr && taken > 0) observer_->on_sent(bytes.first(taken));
    return taken;
}

bool RawLink::vanish() {
    if (fd_ < 0) return false;
    const int on = 1;
    if (::setsockopt(fd_, IPPROTO_TCP, TCP_REPAIR, &on, sizeof on) != 0) return false;
    // In repair mode close() frees the socket silently; the capture shows no close either.
    tls_ = nullptr;
    channel_.reset();
    fd_ = -1;
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
    // Records already decrypted need no wait for the socket; an interrupted wait returns Data
    // with nothing, and the caller loops and checks the deadline again.
    if (!channel_->has_input() && !wait_ready(fd_, POLLIN, deadline)) return Fill::Timeout;
    const Fill fill = read_plain(detail, chunk, got);
    if (got > 0 && observer_ != nullptr) observer_->on_received(chunk.first(got));
    return fill;
}

RawLink::Fill RawLink::read_plain(std::string& detail, std::span<std::uint8_t> chunk,
                                  std::size_t& got) {
    const auto io = channel_->read(chunk);
    switch (io.status) {
        case Status::Done:
            got = io.bytes;
            return Fill::Data;
        case Status::WouldBlock:  // a record not whole yet
            return Fill::Data;
        case Status::EndOfInput:
            if (!tls_) {
                detail = "connection closed by peer";
            } else if (tls_->session().state() == TlsState::Closed) {
                detail = "the server closed the TLS session (close_notify)";
            } else {
                detail = "connection closed by peer (without TLS close_notify)";
            }
            return Fill::Closed;
        case Status::Failed:
            break;
    }
    detail = io.code != 0 ? errno_text(io.code) : "TLS: " + channel_->error();
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
