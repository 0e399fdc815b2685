#include "conformance/client_exam_tcp_wire.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <optional>

#include "transport/socket_channel.hpp"
#include "transport/tls_stream.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

constexpr auto kPollSlice = 20ms;  // how often a running client's exit is looked for

// The client's end as the capture's local side, the examiner's as its peer (the device's).
client::LinkAddresses addresses_of(int fd) {
    client::LinkAddresses addresses;
    sockaddr_storage ends[2]{};
    socklen_t sizes[2] = {sizeof ends[0], sizeof ends[1]};
    ::getpeername(fd, reinterpret_cast<sockaddr*>(&ends[0]), &sizes[0]);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&ends[1]), &sizes[1]);
    addresses.ipv6 = ends[0].ss_family == AF_INET6;
    const auto take = [&](const sockaddr_storage& end, std::array<std::uint8_t, 16>& ip,
                          std::uint16_t& port) {
        if (addresses.ipv6) {
            const auto& in6 = reinterpret_cast<const sockaddr_in6&>(end);
            std::memcpy(ip.data(), &in6.sin6_addr, 16);
            port = ntohs(in6.sin6_port);
        } else {
            const auto& in4 = reinterpret_cast<const sockaddr_in&>(end);
            std::memcpy(ip.data(), &in4.sin_addr, 4);
            port = ntohs(in4.sin_port);
        }
    };
    take(ends[0], addresses.local_ip, addresses.local_port);
    take(ends[1], addresses.peer_ip, addresses.peer_port);
    return addresses;
}

// One accepted connection: its descriptor, to poll and to reset, and the channel bytes take.
struct Link {
    int fd = -1;
    std::unique_ptr<transport::Channel> channel;
};

class TcpWire final : public ExamWire {
  public:
    TcpWire(ClientExaminer& exam, int listen_fd, Capture* capture, security::SharedContext tls)
        : exam_(exam), listen_fd_(listen_fd), capture_(capture), tls_(std::move(tls)) {
        if (capture_) capture_->on_label(exam.scenario().id);
    }
    TcpWire(const TcpWire&) = delete;
    TcpWire& operator=(const TcpWire&) = delete;
    ~TcpWire() override {
        if (captured_) end_capture(*captured_, true);
    }

    void add_polls(std::vector<pollfd>& polls) const override {
        polls.push_back({listen_fd_, POLLIN, 0});
        for (const auto& [id, link] : links_) {
            const bool out = link.channel->wants_write();
            polls.push_back(
                {link.fd, static_cast<short>(POLLIN | (out ? POLLOUT : 0)), 0});  // NOLINT
        }
    }

    void on_polled(const std::vector<pollfd>& polls) override {
        for (const auto& polled : polls) {
            if (polled.revents == 0) continue;
            if (polled.fd == listen_fd_) {
                accept_all();
                continue;
            }
            for (auto& [id, link] : links_) {
                if (link.fd != polled.fd) continue;
                if (link.channel->wants_write()) link.channel->flush();
                read_from(id);
            }
        }
        forget_closed();
    }

    void perform() override {
        for (auto& action : exam_.due(Clock::now())) {
            const auto found = links_.find(action.connection);
            if (found == links_.end()) continue;
            auto& channel = *found->second.channel;
            switch (action.kind) {
                case ClientExaminer::Action::Kind::Send:
                    channel.write(action.bytes);
                    if (captured(action.connection)) capture_->on_received(action.bytes);
                    break;
                case ClientExaminer::Action::Kind::Close:
                    // A FIN (after TLS's close_notify); what the client sends after it is read
                    // and dropped until it closes.
                    channel.shutdown_write();
                    end_capture(action.connection, true);
                    break;
                case ClientExaminer::Action::Kind::Reset: {
                    end_capture(action.connection, true);
                    const linger abort{1, 0};  // closing the socket then sends an RST
                    ::setsockopt(found->second.fd, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
                    links_.erase(found);
                    break;
                }
            }
        }
    }

    std::chrono::milliseconds wait() const override {
        const auto deadline = exam_.deadline();
        if (deadline == Clock::time_point::max()) return kPollSlice;
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        return std::clamp(left, 0ms, std::chrono::milliseconds(kPollSlice));
    }

  private:
    // A capture holds one connection at a time: it follows the newest, and the bytes of an older
    // one still open (a client's second connection overlapping its first) are left out.
    bool captured(std::size_t id) const { return capture_ && captured_ == id; }
    void end_capture(std::size_t id, bool by_examiner) {
        if (!captured(id)) return;
        capture_->on_close(by_examiner);
        captured_.reset();
    }

    void accept_all() {
        while (true) {
            const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
            if (fd < 0) return;
            const int on = 1;
            // Each action is one segment (one TLS record): split answers must not be joined.
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
            const auto id = exam_.opened(Clock::now());
            Link link{fd, std::make_unique<transport::SocketChannel>(fd)};
            if (tls_) {
                link.channel = std::make_unique<transport::TlsStream>(
                    std::move(link.channel), tls_, transport::TlsStream::Side::Server);
            }
            if (capture_) {
                capture_->on_open(addresses_of(fd));
                captured_ = id;
            }
            links_.emplace(id, std::move(link));
            read_from(id);  // a TLS client's hello may be there already
        }
    }

    void read_from(std::size_t id) {
        std::uint8_t buffer[1024];
        auto& channel = *links_.at(id).channel;
        while (true) {
            const auto io = channel.read(buffer);
            if (io.status == transport::Io::Status::Done && io.bytes > 0) {
                const std::span<const std::uint8_t> got(buffer, io.bytes);
                if (captured(id)) capture_->on_sent(got);
                exam_.received(id, got, Clock::now());
                continue;
            }
            if (io.status == transport::Io::Status::WouldBlock ||
                io.status == transport::Io::Status::Done)
                return;
            end_capture(id, false);
            // A socket says why by errno; only TLS has words: the handshake's failure.
            if (io.status == transport::Io::Status::Failed && !channel.error().empty())
                exam_.refused(id, channel.error());
            exam_.closed(id, Clock::now());
            closed_.push_back(id);
            return;
        }
    }

    void forget_closed() {
        for (const auto id : closed_)
            links_.erase(id);
        closed_.clear();
    }

    ClientExaminer& exam_;
    int listen_fd_;
    Capture* capture_;
    security::SharedContext tls_;
    std::optional<std::size_t> captured_;
    std::map<std::size_t, Link> links_;
    std::vector<std::size_t> closed_;
};

}  // namespace

std::unique_ptr<ExamWire> make_tcp_wire(ClientExaminer& exam, int listen_fd, Capture* capture,
                                        security::SharedContext tls) {
    return std::make_unique<TcpWire>(exam, listen_fd, capture, std::move(tls));
}

void drain_backlog(int listen_fd) {
    while (true) {
        const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        ::close(fd);
    }
}

}  // namespace mblab::conformance
