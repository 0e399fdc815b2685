#pragma once

// Captures built byte by byte for the tests of the pcap reader and the learner: classic pcap and
// pcapng in either byte order, Ethernet (with VLAN tags), Linux cooked and raw IP link types, IPv4
// and IPv6, and one client's TCP connection to port 502 as the packets a capture holds.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "robustness/learn.hpp"
#include "robustness/pcap_reader.hpp"
#include "support/hex.hpp"

namespace mblab::robustness::capture_test {

using test::hex;
using Bytes = std::vector<std::uint8_t>;

inline void append(Bytes& out, const Bytes& more) {
    out.insert(out.end(), more.begin(), more.end());
}

inline Bytes be(std::uint32_t value, int size) {
    Bytes out;
    for (int i = size - 1; i >= 0; --i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    return out;
}

inline Bytes le(std::uint32_t value, int size) {
    Bytes out;
    for (int i = 0; i < size; ++i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    return out;
}

inline Bytes in_order(bool big, std::uint32_t value, int size) {
    return big ? be(value, size) : le(value, size);
}

// A TCP header of 20 bytes (checksums are not read).
inline Bytes tcp(std::uint16_t from, std::uint16_t to, std::uint32_t seq, std::uint8_t flags,
                 const Bytes& payload) {
    Bytes out = be(from, 2);
    append(out, be(to, 2));
    append(out, be(seq, 4));
    append(out, hex("00000000 50"));
    out.push_back(flags);
    append(out, hex("FFFF 0000 0000"));
    append(out, payload);
    return out;
}

inline Bytes ipv4(const Bytes& src, const Bytes& dst, const Bytes& segment,
                  std::uint16_t fragment = 0) {
    Bytes out = hex("45 00");
    append(out, be(static_cast<std::uint32_t>(20 + segment.size()), 2));
    append(out, hex("0001"));
    append(out, be(fragment, 2));
    append(out, hex("40 06 0000"));
    append(out, src);
    append(out, dst);
    append(out, segment);
    return out;
}

inline constexpr std::uint16_t kPort = 502;
inline constexpr std::uint16_t kClientPort = 40001;

// One client's connection to port 502, as the IP packets a capture holds. Sequence numbers count
// from the SYN, as the stacks do.
class Talk {
  public:
    // An IPv6 extension header of type `extension_type` may come before TCP.
    explicit Talk(bool ipv6 = false, Bytes extension = {}, std::uint8_t extension_type = 0)
        : ipv6_(ipv6), extension_(std::move(extension)), extension_type_(extension_type) {}

    Talk& open() {
        packets_.push_back(packet(true, client_seq_ - 1, 0x02, {}));
        packets_.push_back(packet(false, server_seq_ - 1, 0x12, {}));
        return *this;
    }
    Talk& ask(const Bytes& bytes) { return send(true, bytes); }
    Talk& answer(const Bytes& bytes) { return send(false, bytes); }
    // A segment at an explicit offset into its direction (retransmissions, reordering).
    Talk& at(bool to_server, std::uint32_t offset, const Bytes& bytes) {
        packets_.push_back(
            packet(to_server, (to_server ? client_start_ : server_start_) + offset, 0x18, bytes));
        return *this;
    }
    const std::vector<Bytes>& packets() const { return packets_; }

  private:
    Talk& send(bool to_server, const Bytes& bytes) {
        auto& seq = to_server ? client_seq_ : server_seq_;
        packets_.push_back(packet(to_server, seq, 0x18, bytes));
        seq += static_cast<std::uint32_t>(bytes.size());
        return *this;
    }
    Bytes packet(bool to_server, std::uint32_t seq, std::uint8_t flags, const Bytes& payload) {
        const Bytes segment = to_server ? tcp(kClientPort, kPort, seq, flags, payload)
                                        : tcp(kPort, kClientPort, seq, flags, payload);
        const Bytes client = ipv6_ ? hex("fd00000000000000 0000000000000001") : hex("0A000001");
        const Bytes server = ipv6_ ? hex("fd00000000000000 0000000000000002") : hex("0A000002");
        const Bytes& src = to_server ? client : server;
        const Bytes& dst = to_server ? server : client;
        if (!ipv6_) return ipv4(src, dst, segment);
        // Next header: TCP, or the extension header that comes first.
        Bytes out = hex("60000000");
        append(out, be(static_cast<std::uint32_t>(extension_.size() + segment.size()), 2));
        out.push_back(extension_.empty() ? 6 : extension_type_);
        out.push_back(64);
        append(out, src);
        append(out, dst);
        append(out, extension_);
        append(out, segment);
        return out;
    }

    bool ipv6_;
    Bytes extension_;
    std::uint8_t extension_type_;
    std::uint32_t client_start_ = 0x10000001;
    std::uint32_t server_start_ = 0xFFFFFFF0;  // wraps past 2^32 within the answers
    std::uint32_t client_seq_ = client_start_;
    std::uint32_t server_seq_ = server_start_;
    std::vector<Bytes> packets_;
};

inline Bytes ethernet(const Bytes& ip, const Bytes& tags = {}) {
    Bytes out = hex("020000000002 020000000001");
    append(out, tags);
    append(out, hex(ip[0] >> 4 == 6 ? "86DD" : "0800"));
    append(out, ip);
    return out;
}

inline Bytes classic(bool big, std::uint32_t link_type, const std::vector<Bytes>& packets,
                     bool nano = false) {
    Bytes out = in_order(big, nano ? 0xA1B23C4D : 0xA1B2C3D4, 4);
    append(out, in_order(big, 2, 2));
    append(out, in_order(big, 4, 2));
    append(out, Bytes(8, 0));
    append(out, in_order(big, 65535, 4));
    append(out, in_order(big, link_type, 4));
    std::uint32_t second = 1700000000;
    for (const auto& p : packets) {
        append(out, in_order(big, second++, 4));
        append(out, in_order(big, 0, 4));
        append(out, in_order(big, static_cast<std::uint32_t>(p.size()), 4));
        append(out, in_order(big, static_cast<std::uint32_t>(p.size()), 4));
        append(out, p);
    }
    return out;
}

inline Bytes block(bool big, std::uint32_t type, Bytes body) {
    while (body.size() % 4 != 0)
        body.push_back(0);
    const auto length = static_cast<std::uint32_t>(body.size() + 12);
    Bytes out = in_order(big, type, 4);
    append(out, in_order(big, length, 4));
    append(out, body);
    append(out, in_order(big, length, 4));
    return out;
}

// A section with one interface; enhanced packet blocks, or simple ones.
inline Bytes pcapng(bool big, std::uint16_t link_type, const std::vector<Bytes>& packets,
                    bool simple = false) {
    Bytes shb = in_order(big, 0x1A2B3C4D, 4);
    append(shb, in_order(big, 1, 2));
    append(shb, in_order(big, 0, 2));
    append(shb, hex("FFFFFFFF FFFFFFFF"));
    Bytes out = block(big, 0x0A0D0D0A, shb);
    Bytes idb = in_order(big, link_type, 2);
    append(idb, hex("0000"));
    append(idb, in_order(big, 262144, 4));
    append(out, block(big, 1, idb));
    // A block the reader does not know (a name resolution block) is skipped.
    append(out, block(big, 4, hex("0000 0000")));
    for (const auto& p : packets) {
        Bytes body;
        if (simple) {
            body = in_order(big, static_cast<std::uint32_t>(p.size()), 4);
        } else {
            body = in_order(big, 0, 4);
            append(body, Bytes(8, 0));
            append(body, in_order(big, static_cast<std::uint32_t>(p.size()), 4));
            append(body, in_order(big, static_cast<std::uint32_t>(p.size()), 4));
        }
        append(body, p);
        append(out, block(big, simple ? 3 : 6, body));
    }
    return out;
}

inline std::vector<Bytes> framed(const std::vector<Bytes>& packets, Bytes (*frame)(const Bytes&)) {
    std::vector<Bytes> out;
    for (const auto& p : packets)
        out.push_back(frame(p));
    return out;
}

// Normal traffic: the lab's usual reads and a write, unit 1; an FC 08 the device refuses with 01.
inline Talk normal_traffic() {
    Talk talk;
    talk.open()
        .ask(hex("0001 0000 0006 01 03 0064 000A"))
        .answer(hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000"))
        .ask(hex("0002 0000 0006 01 04 0000 0002"))
        .answer(hex("0002 0000 0007 01 04 04 00000000"))
        .ask(hex("0003 0000 0006 01 06 0065 1234"))
        .answer(hex("0003 0000 0006 01 06 0065 1234"))
        .ask(hex("0004 0000 0006 01 01 0000 0010"))
        .answer(hex("0004 0000 0005 01 01 02 0000"))
        .ask(hex("0005 0000 0006 01 03 0000 0002"))
        .answer(hex("0005 0000 0007 01 03 04 00000000"))
        .ask(hex("0006 0000 0006 01 08 0000 1234"))
        .answer(hex("0006 0000 0003 01 88 01"))
        // Answered with 02: served, but the addresses are not.
        .ask(hex("0007 0000 0006 01 03 2710 0001"))
        .answer(hex("0007 0000 0003 01 83 02"));
    return talk;
}

inline Recon learned(const Bytes& file, std::uint16_t port = kPort) {
    const auto capture = read_pcap(file);
    EXPECT_TRUE(capture) << capture.error();
    if (!capture) return {};
    const auto recon = learn_recon(*capture, port, "normal.pcap");
    EXPECT_TRUE(recon) << recon.error();
    return recon ? *recon : Recon{};
}

inline std::string ranges_of(const Recon& recon, Table table) {
    std::string out;
    for (const auto& r : recon.ranges.of(table))
        out += std::to_string(r.first) + "-" + std::to_string(r.last) + " ";
    return out;
}

// What a file teaches, in short: the counts of its source line and one table's ranges.
inline void expect_learned(const Bytes& file, const std::string& counts, Table table,
                           const std::string& ranges) {
    const auto recon = learned(file);
    EXPECT_EQ(recon.source, "learned from normal.pcap (" + counts + ")");
    EXPECT_EQ(ranges_of(recon, table), ranges);
}

inline void expect_normal_facts(const Recon& recon) {
    EXPECT_EQ(recon.unit, 1);
    EXPECT_EQ(recon.served, (std::vector<std::uint8_t>{0x01, 0x03, 0x04, 0x06}));
    EXPECT_EQ(recon.not_served, (std::vector<std::uint8_t>{0x08}));
    EXPECT_TRUE(recon.silent.empty());
    EXPECT_EQ(recon.check_address, 0);
    EXPECT_EQ(recon.max_read, 10);
    EXPECT_FALSE(recon.answers_unit_0);
    EXPECT_FALSE(recon.answers_unit_255);
    EXPECT_EQ(ranges_of(recon, Table::HoldingRegisters), "0-1 100-109 ");
    EXPECT_EQ(ranges_of(recon, Table::InputRegisters), "0-1 ");
    EXPECT_EQ(ranges_of(recon, Table::Coils), "0-15 ");
    EXPECT_EQ(ranges_of(recon, Table::DiscreteInputs), "");
    EXPECT_EQ(recon.source, "learned from normal.pcap (7 requests, 7 answers)");
}

}  // namespace mblab::robustness::capture_test
