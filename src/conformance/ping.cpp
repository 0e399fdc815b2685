#include <arpa/inet.h>
#include <fmt/core.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/ip.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <set>
#include <vector>

#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"
#include "conformance/session.hpp"

// Seed 000 7.2: ten 32-byte ICMP echo requests must all be answered. An unprivileged ICMP
// datagram socket works where net.ipv4.ping_group_range includes our group; a raw socket needs
// root or CAP_NET_RAW. With neither, the case is NOT RUN rather than guessed.
namespace mblab::conformance {

namespace {

constexpr std::uint8_t kEchoRequest = 8;
constexpr std::uint8_t kEchoReply = 0;

class Socket {
  public:
    explicit Socket(int fd) : fd_(fd) {}
    Socket(const Socket&) = delete;
    Socket& operator=(const Socket&) = delete;
    ~Socket() {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }

  private:
    int fd_;
};

std::uint16_t checksum(const std::vector<std::uint8_t>& bytes) {
    std::uint32_t sum = 0;
    for (std::size_t i = 0; i + 1 < bytes.size(); i += 2)
        sum += (bytes[i] << 8) | bytes[i + 1];
    if (bytes.size() % 2 != 0) sum += bytes.back() << 8;
    while (sum >> 16)
        sum = (sum & 0xFFFF) + (sum >> 16);
    return static_cast<std::uint16_t>(~sum);
}

std::vector<std::uint8_t> echo_request(std::uint16_t id, std::uint16_t sequence,
                                       std::size_t payload) {
    std::vector<std::uint8_t> packet = {kEchoRequest,
                                        0,
                                        0,
                                        0,
                                        static_cast<std::uint8_t>(id >> 8),
                                        static_cast<std::uint8_t>(id & 0xFF),
                                        static_cast<std::uint8_t>(sequence >> 8),
                                        static_cast<std::uint8_t>(sequence & 0xFF)};
    for (std::size_t i = 0; i < payload; ++i)
        packet.push_back(static_cast<std::uint8_t>('a' + i % 23));
    std::uint16_t sum = checksum(packet);
    packet[2] = static_cast<std::uint8_t>(sum >> 8);
    packet[3] = static_cast<std::uint8_t>(sum & 0xFF);
    return packet;
}

std::string ping_group_range() {
    std::ifstream file("/proc/sys/net/ipv4/ping_group_range");
    std::string low, high;
    if (!(file >> low >> high)) return "unknown";
    return low + " " + high;
}

}  // namespace

Outcome run_ping(Session& session, const Case& c) {
    const auto count = static_cast<std::uint16_t>(param(c, "count"));
    const auto payload = static_cast<std::size_t>(param(c, "payload"));
    const auto timeout = std::chrono::milliseconds(param(c, "timeout_ms"));

    const auto host = session.host();
    if (!host) {
        return Outcome{Verdict::NotApplicable,
                       fmt::format("the device is on a serial line ({}): it has no IP address",
                                   session.dut().serial_framing),
                       {}};
    }
    addrinfo hints{};
    hints.ai_family = AF_INET;
    addrinfo* found = nullptr;
    if (::getaddrinfo(host->c_str(), nullptr, &hints, &found) != 0) {
        return Outcome{
            Verdict::NotRun, fmt::format("cannot resolve {} to an IPv4 address", *host), {}};
    }
    sockaddr_in target = *reinterpret_cast<sockaddr_in*>(found->ai_addr);
    ::freeaddrinfo(found);

    bool raw = false;
    int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, IPPROTO_ICMP);
    if (fd < 0) {
        fd = ::socket(AF_INET, SOCK_RAW | SOCK_CLOEXEC, IPPROTO_ICMP);
        raw = true;
    }
    if (fd < 0) {
        return Outcome{Verdict::NotRun,
                       fmt::format("no ICMP socket: net.ipv4.ping_group_range ({}) excludes group "
                                   "{}, and a raw socket needs root or CAP_NET_RAW ({})",
                                   ping_group_range(), ::getgid(), std::strerror(errno)),
                       {}};
    }
    Socket socket(fd);
    const char* method = raw ? "raw ICMP socket" : "unprivileged ICMP datagram socket";
    // A datagram socket gets its id from the kernel, which also routes only our replies to us.
    const auto id = static_cast<std::uint16_t>(::getpid() & 0xFFFF);

    for (std::uint16_t sequence = 1; sequence <= count; ++sequence) {
        auto packet = echo_request(id, sequence, payload);
        if (::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&target),
                     sizeof target) < 0) {
            return Outcome{Verdict::Fail,
                           fmt::format("sending echo request {} failed: {} ({})", sequence,
                                       std::strerror(errno), method),
                           {}};
        }
    }
    std::set<std::uint16_t> replies;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (replies.size() < count) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        pollfd pfd{fd, POLLIN, 0};
        if (left.count() <= 0 || ::poll(&pfd, 1, static_cast<int>(left.count())) <= 0) break;
        std::uint8_t buffer[1500];
        ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
        if (n <= 0) break;
        std::size_t offset = raw ? static_cast<std::size_t>((buffer[0] & 0x0F) * 4) : 0;
        if (static_cast<std::size_t>(n) < offset + 8 + payload) continue;
        const std::uint8_t* icmp = buffer + offset;
        const auto reply_id = static_cast<std::uint16_t>(icmp[4] << 8 | icmp[5]);
        const auto sequence = static_cast<std::uint16_t>(icmp[6] << 8 | icmp[7]);
        if (icmp[0] != kEchoReply || (raw && reply_id != id) || sequence < 1 || sequence > count) {
            continue;
        }
        replies.insert(sequence);
    }
    std::string summary = fmt::format("{}/{} replies to {}-byte echo requests via {}",
                                      replies.size(), count, payload, method);
    if (replies.size() == count) return Outcome{Verdict::Pass, summary, {}};
    return Outcome{Verdict::Fail, summary + fmt::format(" (waited {} ms)", timeout.count()), {}};
}

}  // namespace mblab::conformance
