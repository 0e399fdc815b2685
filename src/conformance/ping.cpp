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

// CTP 7.2: ten 32-byte ICMP echo requests must all be answered, over ICMPv6 when the device
// is reached over IPv6. An unprivileged ICMP datagram socket works where
// net.ipv4.ping_group_range includes our group (it governs ICMPv6 datagram sockets too); a raw
// socket needs root or CAP_NET_RAW. With neither, the case is NOT RUN rather than guessed.
namespace mblab::conformance {

namespace {

// What differs between ICMP and ICMPv6 echo. The kernel fills in ICMPv6 checksums itself (they
// cover a pseudo-header only it knows), and a raw ICMPv6 socket hands over no IP header.
struct Icmp {
    int family;
    int protocol;
    std::uint8_t echo_request;
    std::uint8_t echo_reply;
    bool we_checksum;
    bool raw_has_ip_header;
    const char* name;
};

constexpr Icmp kIcmp4{AF_INET, IPPROTO_ICMP, 8, 0, true, true, "ICMP"};
constexpr Icmp kIcmp6{AF_INET6, IPPROTO_ICMPV6, 128, 129, false, false, "ICMPv6"};

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

std::vector<std::uint8_t> echo_request(const Icmp& icmp, std::uint16_t id, std::uint16_t sequence,
                                       std::size_t payload) {
    std::vector<std::uint8_t> packet = {icmp.echo_request,
                                        0,
                                        0,
                                        0,
                                        static_cast<std::uint8_t>(id >> 8),
                                        static_cast<std::uint8_t>(id & 0xFF),
                                        static_cast<std::uint8_t>(sequence >> 8),
                                        static_cast<std::uint8_t>(sequence & 0xFF)};
    for (std::size_t i = 0; i < payload; ++i)
        packet.push_back(static_cast<std::uint8_t>('a' + i % 23));
    if (!icmp.we_checksum) return packet;
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
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;  // one entry per address rather than three
    addrinfo* found = nullptr;
    if (int rc = ::getaddrinfo(host->c_str(), nullptr, &hints, &found); rc != 0) {
        return Outcome{
            Verdict::NotRun, fmt::format("cannot resolve {}: {}", *host, ::gai_strerror(rc)), {}};
    }
    sockaddr_storage target{};
    std::memcpy(&target, found->ai_addr, found->ai_addrlen);
    const auto target_size = static_cast<socklen_t>(found->ai_addrlen);
    const Icmp& icmp = found->ai_family == AF_INET6 ? kIcmp6 : kIcmp4;
    ::freeaddrinfo(found);

    bool raw = false;
    int fd = ::socket(icmp.family, SOCK_DGRAM | SOCK_CLOEXEC, icmp.protocol);
    if (fd < 0) {
        fd = ::socket(icmp.family, SOCK_RAW | SOCK_CLOEXEC, icmp.protocol);
        raw = true;
    }
    if (fd < 0) {
        return Outcome{Verdict::NotRun,
                       fmt::format("no {} socket: net.ipv4.ping_group_range ({}) excludes group "
                                   "{}, and a raw socket needs root or CAP_NET_RAW ({})",
                                   icmp.name, ping_group_range(), ::getgid(), std::strerror(errno)),
                       {}};
    }
    Socket socket(fd);
    const std::string method = raw ? fmt::format("raw {} socket", icmp.name)
                                   : fmt::format("unprivileged {} datagram socket", icmp.name);
    // A datagram socket gets its id from the kernel, which also routes only our replies to us.
    const auto id = static_cast<std::uint16_t>(::getpid() & 0xFFFF);

    for (std::uint16_t sequence = 1; sequence <= count; ++sequence) {
        auto packet = echo_request(icmp, id, sequence, payload);
        if (::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&target),
                     target_size) < 0) {
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
        std::size_t offset =
            raw && icmp.raw_has_ip_header ? static_cast<std::size_t>((buffer[0] & 0x0F) * 4) : 0;
        if (static_cast<std::size_t>(n) < offset + 8 + payload) continue;
        const std::uint8_t* reply = buffer + offset;
        const auto reply_id = static_cast<std::uint16_t>(reply[4] << 8 | reply[5]);
        const auto sequence = static_cast<std::uint16_t>(reply[6] << 8 | reply[7]);
        if (reply[0] != icmp.echo_reply || (raw && reply_id != id) || sequence < 1 ||
            sequence > count) {
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
