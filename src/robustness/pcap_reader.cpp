#include "robustness/pcap_reader.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <optional>

#include "conformance/pcap_format.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::span<const std::uint8_t>;
using Error = std::string;

using namespace conformance::pcap;

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherIpv6 = 0x86DD;

std::uint16_t be16(Bytes b, std::size_t at) {
    return static_cast<std::uint16_t>(b[at] << 8 | b[at + 1]);
}

std::uint32_t be32(Bytes b, std::size_t at) {
    return static_cast<std::uint32_t>(be16(b, at)) << 16 | be16(b, at + 2);
}

// A file's fields in the byte order its magic announced.
struct Order {
    bool big = false;
    std::uint16_t u16(Bytes b, std::size_t at) const {
        return big ? be16(b, at) : static_cast<std::uint16_t>(b[at] | b[at + 1] << 8);
    }
    std::uint32_t u32(Bytes b, std::size_t at) const {
        return big ? be32(b, at)
                   : static_cast<std::uint32_t>(u16(b, at)) |
                         static_cast<std::uint32_t>(u16(b, at + 2)) << 16;
    }
};

std::array<std::uint8_t, 16> address(Bytes b, std::size_t at, std::size_t size) {
    std::array<std::uint8_t, 16> out{};
    std::copy_n(b.begin() + static_cast<long>(at), size, out.begin());
    return out;
}

void read_tcp(Bytes tcp, TcpSegment segment, PcapContents& out) {
    if (tcp.size() < 20) return;
    const std::size_t header = static_cast<std::size_t>(tcp[12] >> 4) * 4;
    if (header < 20 || header > tcp.size()) return;
    segment.src_port = be16(tcp, 0);
    segment.dst_port = be16(tcp, 2);
    segment.seq = be32(tcp, 4);
    segment.flags = tcp[13];
    segment.payload.assign(tcp.begin() + static_cast<long>(header), tcp.end());
    out.segments.push_back(std::move(segment));
}

void read_ipv4(Bytes ip, PcapContents& out) {
    if (ip.size() < 20) return;
    const std::size_t header = static_cast<std::size_t>(ip[0] & 0x0F) * 4;
    const std::size_t total = be16(ip, 2);
    if (header < 20 || total < header || header > ip.size()) return;
    // Fragments are not reassembled: Modbus/TCP frames are far below any MTU.
    if ((be16(ip, 6) & 0x3FFF) != 0 || ip[9] != kTcp) return;
    TcpSegment segment;
    segment.src_ip = address(ip, 12, 4);
    segment.dst_ip = address(ip, 16, 4);
    // The total length leaves out Ethernet's padding of short frames; a capture cut by the snap
    // length has less than it says.
    read_tcp(ip.subspan(header, std::min(total, ip.size()) - header), std::move(segment), out);
}

void read_ipv6(Bytes ip, PcapContents& out) {
    if (ip.size() < 40) return;
    const std::size_t payload = be16(ip, 4);
    if (payload == 0) return;  // a jumbogram: not Modbus
    std::uint8_t next = ip[6];
    std::size_t at = 40;
    const std::size_t end = std::min(ip.size(), 40 + payload);
    // Hop-by-hop, routing and destination options say their length; a fragment header, ESP or
    // anything unknown ends the walk.
    while (next == 0 || next == 43 || next == 60) {
        if (at + 2 > end) return;
        const std::size_t length = (static_cast<std::size_t>(ip[at + 1]) + 1) * 8;
        next = ip[at];
        at += length;
    }
    if (next != kTcp || at > end) return;
    TcpSegment segment;
    segment.ipv6 = true;
    segment.src_ip = address(ip, 8, 16);
    segment.dst_ip = address(ip, 24, 16);
    read_tcp(ip.subspan(at, end - at), std::move(segment), out);
}

void read_ip(Bytes ip, PcapContents& out) {
    if (ip.empty()) return;
    if (ip[0] >> 4 == 4) read_ipv4(ip, out);
    if (ip[0] >> 4 == 6) read_ipv6(ip, out);
}

void read_ethertype(std::uint16_t type, Bytes rest, PcapContents& out) {
    if (type == kEtherIpv4) read_ipv4(rest, out);
    if (type == kEtherIpv6) read_ipv6(rest, out);
}

void read_packet(std::uint16_t link_type, Bytes packet, PcapContents& out) {
    ++out.packets;
    switch (link_type) {
        case kLinkEthernet: {
            std::size_t at = 12;
            if (packet.size() < at + 2) return;
            std::uint16_t type = be16(packet, at);
            // 802.1Q, 802.1ad and the older QinQ tag: 4 bytes each, stacked.
            while ((type == 0x8100 || type == 0x88A8 || type == 0x9100) &&
                   packet.size() >= at + 6) {
                at += 4;
                type = be16(packet, at);
            }
            read_ethertype(type, packet.subspan(at + 2), out);
            return;
        }
        case kLinkNull:
            // The address family is in the capturing host's byte order and its value differs
            // between systems for IPv6; the IP version nibble says the same.
            if (packet.size() > 4) read_ip(packet.subspan(4), out);
            return;
        case kLinkRaw:
        case kLinkIpv4:
        case kLinkIpv6:
            read_ip(packet, out);
            return;
        case kLinkSll:
            if (packet.size() >= 16) read_ethertype(be16(packet, 14), packet.subspan(16), out);
            return;
        case kLinkSll2:
            if (packet.size() >= 20) read_ethertype(be16(packet, 0), packet.subspan(20), out);
            return;
        default:
            return;
    }
}

std::optional<Error> read_classic(Bytes file, Order order, PcapContents& out) {
    if (file.size() < 24) return fmt::format("pcap header cut short at offset {}", file.size());
    const auto link_type = static_cast<std::uint16_t>(order.u32(file, 20) & 0xFFFF);
    for (std::size_t at = 24; at < file.size();) {
        if (file.size() - at < 16)
            return fmt::format("pcap packet record header cut short at offset {}", at);
        const std::uint32_t captured = order.u32(file, at + 8);
        if (captured > file.size() - at - 16)
            return fmt::format("pcap packet at offset {} claims {} bytes, {} remain", at, captured,
                               file.size() - at - 16);
        read_packet(link_type, file.subspan(at + 16, captured), out);
        at += 16 + captured;
    }
    return std::nullopt;
}

struct Interface {
    std::uint16_t link_type = 0;
    std::uint32_t snap_length = 0;
};

std::optional<Error> read_pcapng(Bytes file, PcapContents& out) {
    Order order;
    std::vector<Interface> interfaces;
    for (std::size_t at = 0; at < file.size();) {
        if (file.size() - at < 12)
            return fmt::format("pcapng block header cut short at offset {}", at);
        const bool section = be32(file, at) == kSectionHeader;
        if (section) {
            // A new section may change the byte order; its interfaces are its own.
            const std::uint32_t magic = be32(file, at + 8);
            if (magic != kByteOrderMagic && magic != kByteOrderMagicSwapped)
                return fmt::format("pcapng section header at offset {} has no byte-order magic",
                                   at);
            order.big = magic == kByteOrderMagic;
            interfaces.clear();
        }
        const std::uint32_t type = order.u32(file, at);
        const std::uint32_t length = order.u32(file, at + 4);
        if (length < 12 || length % 4 != 0)
            return fmt::format("pcapng block at offset {} has length {}", at, length);
        if (length > file.size() - at)
            return fmt::format("pcapng block at offset {} claims {} bytes, {} remain", at, length,
                               file.size() - at);
        if (order.u32(file, at + length - 4) != length)
            return fmt::format("pcapng block at offset {}: its two lengths differ", at);
        const Bytes body = file.subspan(at + 8, length - 12);
        if (section && body.size() < 16)
            return fmt::format("pcapng section header at offset {} is too short", at);
        if (type == kInterfaceDescription) {
            if (body.size() < 8)
                return fmt::format("pcapng interface block at offset {} is too short", at);
            interfaces.push_back({order.u16(body, 0), order.u32(body, 4)});
        } else if (type == kEnhancedPacket) {
            if (body.size() < 20)
                return fmt::format("pcapng packet block at offset {} is too short", at);
            const std::uint32_t id = order.u32(body, 0);
            const std::uint32_t captured = order.u32(body, 12);
            if (id >= interfaces.size())
                return fmt::format(
                    "pcapng packet block at offset {} names interface {}, not described", at, id);
            if (captured > body.size() - 20)
                return fmt::format("pcapng packet block at offset {} claims {} bytes, {} remain",
                                   at, captured, body.size() - 20);
            read_packet(interfaces[id].link_type, body.subspan(20, captured), out);
        } else if (type == kSimplePacket) {
            if (body.size() < 4 || interfaces.empty())
                return fmt::format("pcapng simple packet block at offset {} without an interface",
                                   at);
            // Its captured length is not written: the smaller of the original length, the
            // interface's snap length and the block.
            std::size_t captured = std::min<std::size_t>(order.u32(body, 0), body.size() - 4);
            if (interfaces[0].snap_length != 0)
                captured = std::min<std::size_t>(captured, interfaces[0].snap_length);
            read_packet(interfaces[0].link_type, body.subspan(4, captured), out);
        }
        at += length;
    }
    return std::nullopt;
}

}  // namespace

protocol::Result<PcapContents, std::string> read_pcap(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < 4) return Error("not a pcap or pcapng file: fewer than 4 bytes at offset 0");
    PcapContents out;
    std::optional<Error> failed;
    const std::uint32_t magic = be32(bytes, 0);
    if (magic == kClassicMicro || magic == kClassicNano) {
        failed = read_classic(bytes, {true}, out);
    } else if (magic == kClassicMicroSwapped || magic == kClassicNanoSwapped) {
        failed = read_classic(bytes, {false}, out);
    } else if (magic == kSectionHeader) {
        failed = read_pcapng(bytes, out);
    } else {
        return fmt::format("not a pcap or pcapng file: magic {:08X} at offset 0", magic);
    }
    if (failed) return *failed;
    return out;
}

}  // namespace mblab::robustness
