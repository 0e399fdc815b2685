#include "web/http_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <map>

namespace mblab::web {

namespace {

using Clock = std::chrono::steady_clock;

// Slow clients hold a slot, not a thread; when every slot is taken, the oldest request still
// coming in is let go for the newcomer.
constexpr std::size_t kMaxConnections = 64;
constexpr int kWorkers = 4;
constexpr std::size_t kMaxStreams = 4;
// A whole request head (or, on a kept-alive connection, the next one) within this, however
// slowly its bytes come; a body and an answer each within their own.
constexpr auto kHeadTime = std::chrono::seconds(10);
constexpr auto kBodyTime = std::chrono::seconds(30);
constexpr auto kWriteTime = std::chrono::seconds(30);
// An event stream whose reader falls this far behind is closed.
constexpr std::size_t kMaxStreamBacklog = 256 * 1024;
// After an answer that ends the connection, what the client still sends (a refused body) is read
// and dropped for a while: closing with unread bytes would reset the connection, and the client
// could lose the answer.
constexpr auto kDrainTime = std::chrono::seconds(2);
constexpr std::size_t kMaxDrain = 4 * kMaxBody;

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

}  // namespace

std::optional<HttpAddress> parse_http_address(const std::string& text, std::string& error) {
    const auto colon = text.rfind(':');
    std::string host = colon == std::string::npos ? std::string() : text.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
        host = host.substr(1, host.size() - 2);
    }
    const std::string port_text = colon == std::string::npos ? text : text.substr(colon + 1);
    unsigned port = 0;
    const auto* end = port_text.data() + port_text.size();
    auto [at, ec] = std::from_chars(port_text.data(), end, port);
    in6_addr any{};
    const bool host_ok = host == "localhost" || ::inet_pton(AF_INET, host.c_str(), &any) == 1 ||
                         ::inet_pton(AF_INET6, host.c_str(), &any) == 1;
    if (colon == std::string::npos || !host_ok || port_text.empty() || ec != std::errc() ||
        at != end || port > 65535) {
        error = fmt::format("'{}': expected HOST:PORT, e.g. 127.0.0.1:8080 (port 0: any free port)",
                            text);
        return std::nullopt;
    }
    return HttpAddress{host == "localhost" ? "127.0.0.1" : host, static_cast<std::uint16_t>(port)};
}

bool is_loopback(const std::string& host) {
    in_addr v4{};
    if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
    return host == "::1";
}

// The socket side: every connection's bytes, phase and deadline, on the I/O thread alone.
struct HttpServer::Loop {
    enum class Phase { Head, Body, Working, Writing, Streaming, Draining };
    struct Connection {
        int fd = -1;
        Phase phase = Phase::Head;
        std::string in;
        std::string out;
        std::size_t sent = 0;
        std::size_t drained = 0;
        HttpRequest request;
        bool close_after = false;
        Clock::time_point opened;
        Clock::time_point deadline;
        const EventRoute* stream = nullptr;
        Clock::time_point next_event;
    };

    HttpServer& server;
    HttpGate gate;
    int listener = -1;
    std::uint64_t next_id = 1;
    std::map<std::uint64_t, Connection> connections;

    Loop(HttpServer& owner, GateOptions options) : server(owner), gate(std::move(options)) {}
    ~Loop() {
        for (auto& [id, c] : connections)
            close_fd(c.fd);
        close_fd(listener);
    }

    void run();
    void accept_all(Clock::time_point now);
    void evict_one();
    void read_from(Connection& c);
    void advance(std::uint64_t id, Connection& c, Clock::time_point now);
    void answer(Connection& c, const HttpReply& reply, bool close, Clock::time_point now);
    void take(std::vector<Done>& done, Clock::time_point now);
    bool write_to(Connection& c, Clock::time_point now);
    std::size_t streams() const {
        return static_cast<std::size_t>(std::count_if(
            connections.begin(), connections.end(),
            [](const auto& entry) { return entry.second.phase == Phase::Streaming; }));
    }
};

void HttpServer::Loop::answer(Connection& c, const HttpReply& reply, bool close,
                              Clock::time_point now) {
    c.close_after = close || !c.request.keep_alive;
    c.out += write_reply(reply, !c.close_after, c.request.method == "HEAD");
    c.phase = Phase::Writing;
    c.deadline = now + kWriteTime;
}

void HttpServer::Loop::advance(std::uint64_t id, Connection& c, Clock::time_point now) {
    if (c.phase == Phase::Head) {
        if (c.in.empty()) return;
        auto head = parse_head(c.in);
        if (head.kind == HeadResult::Kind::NeedMore) return;
        if (head.kind == HeadResult::Kind::Refused) {
            c.request = {};
            answer(c, json_error(head.status, head.reason), true, now);
            return;
        }
        c.request = std::move(head.request);
        c.in.erase(0, head.used);
        // Refused on its head alone: a body from someone without the token is never read.
        if (auto refusal = gate.check(c.request)) {
            answer(c, *refusal, true, now);
            return;
        }
        c.phase = Phase::Body;
        c.deadline = now + kBodyTime;
        if (c.request.expects_continue && c.in.size() < c.request.body_length) {
            c.out += "HTTP/1.1 100 Continue\r\n\r\n";
        }
    }
    if (c.phase == Phase::Body) {
        if (c.in.size() < c.request.body_length) return;
        c.request.body = c.in.substr(0, c.request.body_length);
        c.in.erase(0, c.request.body_length);
        c.phase = Phase::Working;
        {
            std::lock_guard lock(server.jobs_mutex_);
            server.jobs_.push_back({id, c.request});
        }
        server.jobs_changed_.notify_one();
    }
}

void HttpServer::Loop::take(std::vector<Done>& done, Clock::time_point now) {
    for (auto& d : done) {
        auto found = connections.find(d.connection);
        if (found == connections.end()) continue;
        auto& c = found->second;
        if (!d.outcome.stream) {
            answer(c, d.outcome.reply, false, now);
        } else if (streams() >= kMaxStreams) {
            answer(c, json_error(503, fmt::format("at most {} event streams at once", kMaxStreams)),
                   false, now);
        } else {
            c.phase = Phase::Streaming;
            c.stream = d.outcome.stream;
            c.out += write_stream_head();
            c.next_event = now;
        }
    }
    done.clear();
}

void HttpServer::Loop::evict_one() {
    auto oldest = connections.end();
    for (auto it = connections.begin(); it != connections.end(); ++it) {
        const auto phase = it->second.phase;
        if (phase != Phase::Head && phase != Phase::Body) continue;
        if (oldest == connections.end() || it->second.opened < oldest->second.opened) oldest = it;
    }
    if (oldest == connections.end()) return;
    close_fd(oldest->second.fd);
    connections.erase(oldest);
}

void HttpServer::Loop::accept_all(Clock::time_point now) {
    for (;;) {
        int fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        if (connections.size() >= kMaxConnections) evict_one();
        if (connections.size() >= kMaxConnections) {
            ::close(fd);
            continue;
        }
        Connection c;
        c.fd = fd;
        c.opened = now;
        c.deadline = now + kHeadTime;
        connections.emplace(next_id++, std::move(c));
    }
}

void HttpServer::Loop::read_from(Connection& c) {
    char buffer[16384];
    // Only what the phase may still need is kept: the head's limit plus one, or the body's rest.
    const bool discard = c.phase == Phase::Streaming || c.phase == Phase::Draining;
    const std::size_t want = c.phase == Phase::Head ? kMaxHead + 1 : c.request.body_length;
    while (discard || c.in.size() < want) {
        const auto n = ::recv(c.fd, buffer, sizeof buffer, 0);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
            close_fd(c.fd);
            return;
        }
        if (n < 0) return;
        if (!discard) {
            c.in.append(buffer, static_cast<std::size_t>(n));
        } else if (c.phase == Phase::Draining &&
                   (c.drained += static_cast<std::size_t>(n)) > kMaxDrain) {
            close_fd(c.fd);
            return;
        }
    }
}

bool HttpServer::Loop::write_to(Connection& c, Clock::time_point now) {
    while (c.sent < c.out.size()) {
        const auto n = ::send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
        if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
        c.sent += static_cast<std::size_t>(n);
    }
    c.out.clear();
    c.sent = 0;
    if (c.phase != Phase::Writing) return true;
    if (c.close_after) {
        ::shutdown(c.fd, SHUT_WR);
        c.phase = Phase::Draining;
        c.deadline = now + kDrainTime;
        return true;
    }
    c.phase = Phase::Head;
    c.request = {};
    c.deadline = now + kHeadTime;
    return true;
}

void HttpServer::Loop::run() {
    std::vector<pollfd> fds;
    std::vector<std::uint64_t> ids;
    std::vector<Done> done;
    for (;;) {
        auto now = Clock::now();
        fds.clear();
        ids.clear();
        fds.push_back({server.wake_fd_, POLLIN, 0});
        fds.push_back({listener, POLLIN, 0});
        auto wake_at = now + std::chrono::seconds(1);
        for (auto& [id, c] : connections) {
            short events = 0;
            if (c.phase != Phase::Working && c.phase != Phase::Writing) events |= POLLIN;
            if (!c.out.empty()) events |= POLLOUT;
            fds.push_back({c.fd, events, 0});
            ids.push_back(id);
            wake_at = std::min(wake_at, c.phase == Phase::Streaming ? c.next_event : c.deadline);
        }
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(wake_at - now);
        ::poll(fds.data(), fds.size(), static_cast<int>(std::max<long>(wait.count(), 0) + 1));
        now = Clock::now();
        if (fds[0].revents & POLLIN) {
            std::uint64_t count = 0;
            (void)!::read(server.wake_fd_, &count, sizeof count);
            std::lock_guard lock(server.jobs_mutex_);
            if (server.stopping_) return;
            done.swap(server.done_);
        }
        take(done, now);
        for (std::size_t i = 0; i < ids.size(); ++i) {
            auto found = connections.find(ids[i]);
            if (found == connections.end()) continue;
            auto& c = found->second;
            const auto revents = fds[i + 2].revents;
            if (revents & (POLLIN | POLLHUP | POLLERR)) read_from(c);
            if (c.fd >= 0 && (revents & POLLOUT) && !write_to(c, now)) close_fd(c.fd);
            if (c.fd >= 0) advance(ids[i], c, now);
            if (c.fd >= 0 && c.phase == Phase::Streaming && now >= c.next_event) {
                auto event = HttpRoutes::next_event(*c.stream, c.request.query);
                if (!event || c.out.size() > kMaxStreamBacklog) {
                    close_fd(c.fd);
                } else {
                    c.out += *event;
                    c.next_event = now + c.stream->period;
                }
            }
            if (c.fd >= 0 && c.phase != Phase::Streaming && c.phase != Phase::Working &&
                now >= c.deadline) {
                close_fd(c.fd);
            }
            if (c.fd >= 0 && !c.out.empty() && !write_to(c, now)) close_fd(c.fd);
            // An answer just went out whole: a request the client pipelined behind it is
            // already here, and no new byte may come to wake the loop for it.
            if (c.fd >= 0 && c.phase == Phase::Head && !c.in.empty()) advance(ids[i], c, now);
            if (c.fd < 0) connections.erase(found);
        }
        if (fds[1].revents & POLLIN) accept_all(now);
    }
}

HttpServer::HttpServer(GateOptions gate) : gate_options_(std::move(gate)) {}

HttpServer::~HttpServer() {
    stop();
}

std::optional<std::uint16_t> HttpServer::start(const HttpAddress& address, std::string& error) {
    const bool v6 = address.host.find(':') != std::string::npos;
    sockaddr_storage storage{};
    socklen_t length = 0;
    if (v6) {
        auto* a = reinterpret_cast<sockaddr_in6*>(&storage);
        a->sin6_family = AF_INET6;
        a->sin6_port = htons(address.port);
        ::inet_pton(AF_INET6, address.host.c_str(), &a->sin6_addr);
        length = sizeof *a;
    } else {
        auto* a = reinterpret_cast<sockaddr_in*>(&storage);
        a->sin_family = AF_INET;
        a->sin_port = htons(address.port);
        ::inet_pton(AF_INET, address.host.c_str(), &a->sin_addr);
        length = sizeof *a;
    }
    int fd = ::socket(v6 ? AF_INET6 : AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    const int on = 1;
    if (fd >= 0) ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&storage), length) != 0 ||
        ::listen(fd, 128) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&storage), &length) != 0) {
        error = fmt::format("cannot listen for HTTP on {}:{}: {}", address.host, address.port,
                            std::strerror(errno));
        if (fd >= 0) ::close(fd);
        return std::nullopt;
    }
    const auto port = ntohs(v6 ? reinterpret_cast<sockaddr_in6*>(&storage)->sin6_port
                               : reinterpret_cast<sockaddr_in*>(&storage)->sin_port);
    wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    auto options = gate_options_;
    options.bound_host = address.host;
    options.port = port;
    loop_ = std::make_unique<Loop>(*this, std::move(options));
    loop_->listener = fd;
    io_thread_ = std::thread([this] { loop_->run(); });
    for (int i = 0; i < kWorkers; ++i)
        workers_.emplace_back([this] { work(); });
    return port;
}

void HttpServer::work() {
    std::unique_lock lock(jobs_mutex_);
    for (;;) {
        jobs_changed_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
        if (stopping_) return;
        auto job = std::move(jobs_.front());
        jobs_.pop_front();
        lock.unlock();
        auto outcome = routes_.route(job.request);
        lock.lock();
        done_.push_back({job.connection, std::move(outcome)});
        const std::uint64_t one = 1;
        (void)!::write(wake_fd_, &one, sizeof one);
    }
}

void HttpServer::stop() {
    {
        std::lock_guard lock(jobs_mutex_);
        if (stopping_) return;
        stopping_ = true;
    }
    jobs_changed_.notify_all();
    if (wake_fd_ >= 0) {
        const std::uint64_t one = 1;
        (void)!::write(wake_fd_, &one, sizeof one);
    }
    if (io_thread_.joinable()) io_thread_.join();
    for (auto& worker : workers_)
        worker.join();
    workers_.clear();
    loop_.reset();
    close_fd(wake_fd_);
}

}  // namespace mblab::web
