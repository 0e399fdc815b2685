// A Modbus/TCP device for the tests of `mblab fuzz`: it answers FC 03 (zeros) and exception 01
// for everything else, over any number of connections, and is fragile in one way chosen on the
// command line, or robust in an unusual one:
//   protocol-id     exits on a frame whose protocol id is not 0 (a crash)
//   length-one      blocks its loop forever on an MBAP length of 1 (a hang)
//   byte-count      stops answering anyone after an FC 10 whose byte count is not 2 x quantity
//   blocking-send   writes answers with blocking sends: a client that never reads its answers
//                   stalls everyone (otherwise such a client is closed)
//   loses-writes    serves FC 06 to registers 0..99 but, given more than 8 requests at once,
//                   acknowledges the writes among them without keeping them
//   few-slots       64 connections at most: a newcomer evicts a connection stuck in a partial
//                   frame but never an idle one, and is closed when there is none
//   probe-23        exits on FC 17 with a write quantity of 0 (the reconnaissance's harmless probe)
//   malformed-23    answers FC 17 with exception 01 like any code it does not serve, but exits on
//                   one whose write quantity is over 121 (it parses before it dispatches)
//   storm-degrades  serves FC 06 on registers 0..99; the first time more than 8 requests come at
//                   once it stalls for 400 ms, then serves as before (it recovers by itself)
//   storm-breaks-writes  as storm-degrades, but after such a storm answers every FC 06 with
//                   exception 04 until restarted (reads still served)
//   stale-register  as storm-degrades, but after such a storm acknowledges FC 06 without keeping
//                   the value: the register silently stops updating
//   slow-accept     serves FC 06 on registers 0..99, but each connection it accepts costs it 10 ms
//                   of work: a storm of connection opens starves everyone else
//   polls-each      serves FC 06 on registers 0..99, but each turn of its loop waits 1 ms on every
//                   connection it holds (a stack polling its sockets in turn) and never times one
//                   out: connections left half-open pile up and slow it for good
//   closes-garbage  robust: closes the connection on anything but a valid FC 03
//   late            robust: answers 150 ms late
//   floods-answers  robust: answers a function code no standard request uses with its exception
//                   repeated for a megabyte, as much of it as the connection takes (a client
//                   must not keep it all)
// Usage: fragile_device MODE PORT PIDFILE
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Client {
    int fd;
    std::vector<std::uint8_t> buffer;
};

std::string g_mode;
bool g_deaf = false;
bool g_stalled = false;  // storm-degrades: once
bool g_broken = false;   // storm-breaks-writes, stale-register: since the first storm
std::array<std::uint16_t, 100> g_registers{};

// Whole requests waiting in `b`.
std::size_t whole_requests(const std::vector<std::uint8_t>& b) {
    std::size_t count = 0;
    for (std::size_t at = 0; at + 7 <= b.size(); ++count) {
        const std::size_t length = b[at + 4] << 8 | b[at + 5];
        if (length < 2 || at + 6 + length > b.size()) break;
        at += 6 + length;
    }
    return count;
}

// False when the connection is to be closed.
bool serve(Client& client) {
    auto& b = client.buffer;
    std::vector<std::uint8_t> out;
    const bool forgetful = g_mode == "loses-writes" && whole_requests(b) > 8;
    const bool monitored = g_mode == "storm-degrades" || g_mode == "storm-breaks-writes" ||
                           g_mode == "stale-register" || g_mode == "slow-accept" ||
                           g_mode == "polls-each";
    const bool stormed =
        g_mode == "storm-degrades" || g_mode == "storm-breaks-writes" || g_mode == "stale-register";
    if (stormed && whole_requests(b) > 8) {
        if (g_mode == "storm-degrades" && !g_stalled) {
            g_stalled = true;
            std::this_thread::sleep_for(std::chrono::milliseconds(400));
        }
        g_broken = g_mode != "storm-degrades";
    }
    while (b.size() >= 7) {
        const unsigned protocol = b[2] << 8 | b[3];
        const unsigned length = b[4] << 8 | b[5];
        if (protocol != 0 && g_mode == "protocol-id") std::_Exit(1);
        if (length == 1 && g_mode == "length-one") {
            while (true)
                ::pause();
        }
        if (protocol != 0 || length < 2 || length > 254) return false;
        if (b.size() < 6 + length) break;
        const std::vector<std::uint8_t> pdu(b.begin() + 7, b.begin() + 6 + length);
        std::vector<std::uint8_t> answer;
        const unsigned quantity = pdu.size() >= 5 ? (pdu[3] << 8 | pdu[4]) : 0;
        const unsigned write_quantity = pdu.size() >= 9 ? (pdu[7] << 8 | pdu[8]) : 1;
        if (pdu[0] == 0x17 && ((g_mode == "probe-23" && write_quantity == 0) ||
                               (g_mode == "malformed-23" && write_quantity > 121)))
            std::_Exit(1);
        if (pdu[0] == 0x10 && pdu.size() >= 6 && pdu[5] != 2 * quantity && g_mode == "byte-count")
            g_deaf = true;
        const unsigned address = pdu.size() >= 3 ? (pdu[1] << 8 | pdu[2]) : 0;
        if (pdu[0] == 0x03 && pdu.size() == 5 && quantity >= 1 && quantity <= 125) {
            answer = {0x03, static_cast<std::uint8_t>(2 * quantity)};
            for (unsigned i = 0; i < quantity; ++i) {
                const auto value = address + i < g_registers.size() ? g_registers[address + i] : 0;
                answer.push_back(static_cast<std::uint8_t>(value >> 8));
                answer.push_back(static_cast<std::uint8_t>(value));
            }
        } else if ((g_mode == "loses-writes" || monitored) && pdu[0] == 0x06) {
            if (g_broken && g_mode == "storm-breaks-writes") {
                answer = {0x86, 0x04};
            } else if (pdu.size() != 5) {
                answer = {0x86, 0x03};
            } else if (address >= g_registers.size()) {
                answer = {0x86, 0x02};
            } else {
                if (!forgetful && !(g_broken && g_mode == "stale-register"))
                    g_registers[address] = static_cast<std::uint16_t>(quantity);
                answer = pdu;
            }
        } else if (g_mode == "closes-garbage") {
            return false;
        } else {
            answer = {static_cast<std::uint8_t>(pdu[0] | 0x80), 0x01};
        }
        const unsigned size = answer.size() + 1;
        // Only codes no standard request uses: the tester's reconnaissance and checks ask
        // standard ones on connections of their own, and would read the flood as answers.
        constexpr std::array<std::uint8_t, 19> kPublic = {1,  2,  3,  4,  5,  6,  7,  8,  11, 12,
                                                          15, 16, 17, 20, 21, 22, 23, 24, 43};
        const bool flood = g_mode == "floods-answers" &&
                           std::find(kPublic.begin(), kPublic.end(), pdu[0]) == kPublic.end();
        const std::size_t frame_at = out.size();
        out.insert(out.end(), {b[0], b[1], 0, 0, static_cast<std::uint8_t>(size >> 8),
                               static_cast<std::uint8_t>(size), b[6]});
        out.insert(out.end(), answer.begin(), answer.end());
        const std::vector<std::uint8_t> frame(out.begin() + static_cast<long>(frame_at), out.end());
        while (flood && out.size() - frame_at < (std::size_t{1} << 20))
            out.insert(out.end(), frame.begin(), frame.end());
        b.erase(b.begin(), b.begin() + 6 + length);
    }
    if (out.empty() || g_deaf) return true;
    // Without blocking, a client whose answers do not fit is closed rather than waited for.
    const int flags = g_mode == "blocking-send" ? MSG_NOSIGNAL : MSG_NOSIGNAL | MSG_DONTWAIT;
    const auto sent = ::send(client.fd, out.data(), out.size(), flags);
    // A flood is as much as the connection takes: the rest is dropped, the client kept.
    if (g_mode == "floods-answers") return sent >= 0 || errno == EAGAIN;
    return sent == static_cast<ssize_t>(out.size());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: fragile_device MODE PORT PIDFILE\n");
        return 2;
    }
    g_mode = argv[1];
    // Thousands of connections at once are a case of their own.
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) == 0) {
        limit.rlim_cur = limit.rlim_max;
        ::setrlimit(RLIMIT_NOFILE, &limit);
    }
    const int listener = ::socket(AF_INET, SOCK_STREAM, 0);
    const int on = 1;
    ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(std::stoi(argv[2])));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    // Restarted, it may start before its killed predecessor has let go of the port.
    bool bound = false;
    for (int attempt = 0; attempt < 250 && !bound; ++attempt) {
        bound = ::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
        if (!bound) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!bound || ::listen(listener, 64) != 0) {
        std::perror("fragile_device");
        return 1;
    }
    if (FILE* pid = std::fopen(argv[3], "w")) {
        std::fprintf(pid, "%d\n", static_cast<int>(::getpid()));
        std::fclose(pid);
    }
    std::vector<Client> clients;
    while (true) {
        std::vector<pollfd> fds{{listener, POLLIN, 0}};
        for (const auto& c : clients)
            fds.push_back({c.fd, POLLIN, 0});
        if (::poll(fds.data(), fds.size(), -1) < 0) continue;
        // Late once per turn of the loop, whatever it serves: slow, never stuck.
        if (g_mode == "late") std::this_thread::sleep_for(std::chrono::milliseconds(150));
        if (g_mode == "polls-each")
            std::this_thread::sleep_for(std::chrono::milliseconds(clients.size()));
        if (fds[0].revents & POLLIN) {
            for (int fd; (fd = ::accept4(listener, nullptr, nullptr, 0)) >= 0;) {
                const auto live = std::count_if(clients.begin(), clients.end(),
                                                [](const Client& c) { return c.fd >= 0; });
                bool admit = true;
                if (g_mode == "slow-accept")
                    std::this_thread::sleep_for(std::chrono::milliseconds(10));
                if (g_mode == "few-slots" && live >= 64) {
                    // Marked, not erased: the poll set below still maps onto `clients`.
                    auto stuck = std::find_if(clients.begin(), clients.end(), [](const Client& c) {
                        return c.fd >= 0 && !c.buffer.empty();
                    });
                    admit = stuck != clients.end();
                    if (admit) {
                        ::close(stuck->fd);
                        stuck->fd = -1;
                    }
                }
                if (admit) {
                    clients.push_back({fd, {}});
                } else {
                    ::close(fd);
                }
                pollfd more{listener, POLLIN, 0};
                if (::poll(&more, 1, 0) <= 0) break;
            }
        }
        for (std::size_t i = 1; i < fds.size(); ++i) {
            if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            Client& client = clients[i - 1];
            std::uint8_t chunk[4096];
            const ssize_t got = ::recv(client.fd, chunk, sizeof chunk, 0);
            bool keep = got > 0;
            if (keep) {
                client.buffer.insert(client.buffer.end(), chunk, chunk + got);
                keep = serve(client);
            }
            if (!keep) {
                ::close(client.fd);
                client.fd = -1;
            }
        }
        std::erase_if(clients, [](const Client& c) { return c.fd < 0; });
    }
}
