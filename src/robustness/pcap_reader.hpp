#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "protocol/result.hpp"

// Captures of normal traffic (classic pcap and pcapng, as tcpdump, dumpcap, Wireshark and
// `mblab conform --pcap` write them) read down to their TCP segments, so that reconnaissance can
// be learned from what a device already answered. Bytes in, segments out: the caller reads the
// file.
namespace mblab::robustness {

struct TcpSegment {
    std::array<std::uint8_t, 16> src_ip{};  // IPv4: the first 4 bytes
    std::array<std::uint8_t, 16> dst_ip{};
    bool ipv6 = false;
    std::uint16_t src_port = 0;
    std::uint16_t dst_port = 0;
    std::uint32_t seq = 0;
    std::uint8_t flags = 0;  // FIN 01, SYN 02, RST 04, PSH 08, ACK 10
    // What was captured of the payload: a packet cut by the snap length has less than was sent,
    // which reassembly sees as a gap.
    std::vector<std::uint8_t> payload;
};

struct PcapContents {
    std::size_t packets = 0;  // packet records, TCP or not
    std::vector<TcpSegment> segments;
};

// Every TCP segment over IPv4 or IPv6, in file order. Skipped without error: packets of link types
// not read, other protocols, IP fragments, IPv6 extension headers that cannot be followed. A file
// that is not a capture, or is cut short, gives one line naming the offset.
//
// Link types: Ethernet (1, 802.1Q/802.1ad tags), BSD null/loopback (0), raw IP (101, 228, 229),
// Linux cooked SLL (113) and SLL2 (276).
protocol::Result<PcapContents, std::string> read_pcap(std::span<const std::uint8_t> bytes);

}  // namespace mblab::robustness
