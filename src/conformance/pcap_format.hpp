#pragma once

#include <cstdint>

// The numbers of the capture file formats (pcapng, draft-ietf-opsawg-pcapng; classic pcap,
// draft-ietf-opsawg-pcap; link types from the tcpdump.org LINKTYPE registry) and of the TCP
// header inside them: one list for the writer of `mblab conform --pcap` and the reader that
// learns from captures (robustness/pcap_reader), so that what one writes the other reads.
namespace mblab::conformance::pcap {

// A file's first four bytes read big-endian, and the pcapng byte-order magic.
enum Magic : std::uint32_t {
    kClassicMicro = 0xA1B2C3D4,         // classic pcap, microsecond timestamps
    kClassicNano = 0xA1B23C4D,          // classic pcap, nanosecond timestamps
    kClassicMicroSwapped = 0xD4C3B2A1,  // the same written by a little-endian host
    kClassicNanoSwapped = 0x4D3CB2A1,
    // The section header's byte-order magic read in the writer's order, and in the other.
    kByteOrderMagic = 0x1A2B3C4D,
    kByteOrderMagicSwapped = 0x4D3C2B1A
};

enum BlockType : std::uint32_t {
    kSectionHeader = 0x0A0D0D0A,  // reads the same in either byte order
    kInterfaceDescription = 1,    // a link type and snap length; packets name it by index
    kSimplePacket = 3,            // interface 0, no timestamp, no captured length
    kEnhancedPacket = 6
};

enum OptionCode : std::uint16_t {
    kEndOfOptions = 0,  // opt_endofopt, in any block
    kComment = 1,       // opt_comment, in any block
    kShbHardware = 2,   // section header options
    kShbOs = 3,
    kShbUserAppl = 4,
    kEpbFlags = 2  // enhanced packet block: inbound 1, outbound 2 in its low bits
};

enum LinkType : std::uint16_t {
    kLinkNull = 0,  // BSD loopback: the address family, then IP
    kLinkEthernet = 1,
    kLinkRaw = 101,  // IPv4 or IPv6 with no link-layer header
    kLinkSll = 113,  // Linux cooked capture, and its second version
    kLinkSll2 = 276,
    kLinkUser0 = 147,  // private use: what an RTU line's frames are written as
    kLinkUser1 = 148,  // private use: what an ASCII line's frames are written as
    kLinkIpv4 = 228,
    kLinkIpv6 = 229
};

// TCP: its IP protocol number, and its header's flags.
enum Tcp : std::uint8_t {
    kTcp = 6,
    kTcpFin = 0x01,
    kTcpSyn = 0x02,
    kTcpPsh = 0x08,
    kTcpAck = 0x10
};

}  // namespace mblab::conformance::pcap
