// mblab's own Modbus/TCP work in the loop of canned_server.c: each connection's bytes go through
// the server's session core (MbapSession) and the shipped reference device, exactly as in
// `mblab serve`, but the loop around them is a bare epoll loop with no Asio, no poller and no
// timers. It answers what `mblab serve` answers for well-behaved clients; it is not a server
// (no idle or partial-frame timeouts, no deferred answers, no connection limit).
//
// In bench/run_server_bench.sh (SERVERS="mblab bare canned") it splits mblab's distance to the
// canned ceiling in two: bare / canned is what the Modbus work costs, mblab / bare what the run
// loop costs.
//
//   bare_mbap_server PORT      (PORT 0: any; the port is printed as "port=N")
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "device/reference_device.hpp"
#include "immediate_host.hpp"
#include "server/mbap_session.hpp"

namespace {

using mblab::server::Clock;
using mblab::server::MbapSession;

using Host = mblab::bench::ImmediateHost;

struct Connection {
    Connection(int descriptor, mblab::device::RequestHandler& device,
               mblab::server::ServerStats& stats, Host& host)
        : fd(descriptor), session(device, {}, stats, host, Clock::now()) {}
    int fd;
    MbapSession session;
};

// Reads once, answers what came; false when the connection is over.
bool serve(Connection& c) {
    const auto now = Clock::now();
    if (c.session.wants_input()) {
        const auto space = c.session.input_space();
        const ssize_t got = ::recv(c.fd, space.data(), space.size(), 0);
        if (got <= 0) return false;
        c.session.received(static_cast<std::size_t>(got), now);
    }
    std::array<iovec, MbapSession::kMaxGather> out{};
    while (const std::size_t parts = c.session.output(now, out)) {
        msghdr message{};
        message.msg_iov = out.data();
        message.msg_iovlen = parts;
        const ssize_t sent = ::sendmsg(c.fd, &message, MSG_NOSIGNAL);
        if (sent <= 0) return false;
        c.session.sent(static_cast<std::size_t>(sent), now);
    }
    return c.session.ending(now) == MbapSession::Ending::Open;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: bare_mbap_server PORT\n");
        return 2;
    }
    auto loaded =
        mblab::device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
    if (!loaded) {
        std::fprintf(stderr, "bare_mbap_server: %s\n", loaded.error().c_str());
        return 1;
    }
    auto& device = **loaded;
    mblab::server::ServerStats stats;
    Host host;

    const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    int one = 1;
    ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(std::atoi(argv[1])));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener, 4096) != 0 ||
        ::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
        std::perror("bare_mbap_server");
        return 1;
    }
    std::printf("port=%d\n", ntohs(address.sin_port));
    std::fflush(stdout);

    const int epoll = ::epoll_create1(EPOLL_CLOEXEC);
    epoll_event event{};
    event.events = EPOLLIN;
    ::epoll_ctl(epoll, EPOLL_CTL_ADD, listener, &event);
    std::array<epoll_event, 256> events{};
    for (;;) {
        const int n = ::epoll_wait(epoll, events.data(), static_cast<int>(events.size()), -1);
        for (int e = 0; e < n; ++e) {
            auto* c = static_cast<Connection*>(events[static_cast<std::size_t>(e)].data.ptr);
            if (c == nullptr) {
                int fd = -1;
                while ((fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC)) >=
                       0) {
                    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    epoll_event add{};
                    add.events = EPOLLIN;
                    add.data.ptr = new Connection(fd, device, stats, host);
                    ::epoll_ctl(epoll, EPOLL_CTL_ADD, fd, &add);
                }
                continue;
            }
            if (!serve(*c)) {
                ::close(c->fd);
                delete c;
            }
        }
    }
}
