// Captures in, reconnaissance out: the pcap reader over every file format and link type it reads,
// and what the learner makes of reassembled Modbus/TCP traffic.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "robustness/learn.hpp"
#include "robustness/pcap_reader.hpp"
#include "support/hex.hpp"

namespace mblab::robustness {
namespace {

using test::hex;
using Bytes = std::vector<std::uint8_t>;

void append(Bytes& out, const Bytes& more) {
    out.insert(out.end(), more.begin(), more.end());
}

Bytes be(std::uint32_t value, int size) {
    Bytes out;
    for (int i = size - 1; i >= 0; --i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    return out;
}

Bytes le(std::uint32_t value, int size) {
    Bytes out;
    for (int i = 0; i < size; ++i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    return out;
}

Bytes in_order(bool big, std::uint32_t value, int size) {
    return big ? be(value, size) : le(value, size);
}

// A TCP header of 20 bytes (checksums are not read).
Bytes tcp(std::uint16_t from, std::uint16_t to, std::uint32_t seq, std::uint8_t flags,
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

Bytes ipv4(const Bytes& src, const Bytes& dst, const Bytes& segment, std::uint16_t fragment = 0) {
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

constexpr std::uint16_t kPort = 502;
constexpr std::uint16_t kClientPort = 40001;

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

Bytes ethernet(const Bytes& ip, const Bytes& tags = {}) {
    Bytes out = hex("020000000002 020000000001");
    append(out, tags);
    append(out, hex(ip[0] >> 4 == 6 ? "86DD" : "0800"));
    append(out, ip);
    return out;
}

Bytes classic(bool big, std::uint32_t link_type, const std::vector<Bytes>& packets,
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

Bytes block(bool big, std::uint32_t type, Bytes body) {
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
Bytes pcapng(bool big, std::uint16_t link_type, const std::vector<Bytes>& packets,
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

std::vector<Bytes> framed(const std::vector<Bytes>& packets, Bytes (*frame)(const Bytes&)) {
    std::vector<Bytes> out;
    for (const auto& p : packets)
        out.push_back(frame(p));
    return out;
}

// Normal traffic: the lab's usual reads and a write, unit 1; an FC 08 the device refuses with 01.
Talk normal_traffic() {
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

Recon learned(const Bytes& file, std::uint16_t port = kPort) {
    const auto capture = read_pcap(file);
    EXPECT_TRUE(capture) << capture.error();
    if (!capture) return {};
    const auto recon = learn_recon(*capture, port, "normal.pcap");
    EXPECT_TRUE(recon) << recon.error();
    return recon ? *recon : Recon{};
}

std::string ranges_of(const Recon& recon, Table table) {
    std::string out;
    for (const auto& r : recon.ranges.of(table))
        out += std::to_string(r.first) + "-" + std::to_string(r.last) + " ";
    return out;
}

// What a file teaches, in short: the counts of its source line and one table's ranges.
void expect_learned(const Bytes& file, const std::string& counts, Table table,
                    const std::string& ranges) {
    const auto recon = learned(file);
    EXPECT_EQ(recon.source, "learned from normal.pcap (" + counts + ")");
    EXPECT_EQ(ranges_of(recon, table), ranges);
}

void expect_normal_facts(const Recon& recon) {
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

// One packet written out in full: Ethernet, IPv4, TCP 40001 -> 502, an FC 03 request.
TEST(PcapReader, ReadsALittleEndianClassicFileByHand) {
    const Bytes file =
        hex("D4C3B2A1 0200 0400 00000000 00000000 FFFF0000 01000000"  // header, Ethernet
            "00F15365 00000000 42000000 42000000"                     // record: 66 bytes
            "020000000002 020000000001 0800"                          // Ethernet
            "4500 0034 0001 4000 4006 0000 0A000001 0A000002"         // IPv4, 52 bytes
            "9C41 01F6 00000064 00000000 5018 FFFF 0000 0000"         // TCP, seq 100, PSH ACK
            "0001 0000 0006 01 03 0064 000A");                        // MBAP + PDU
    const auto capture = read_pcap(file);
    ASSERT_TRUE(capture) << capture.error();
    EXPECT_EQ(capture->packets, 1U);
    ASSERT_EQ(capture->segments.size(), 1U);
    const auto& s = capture->segments[0];
    EXPECT_FALSE(s.ipv6);
    EXPECT_EQ(test::to_hex(std::span(s.src_ip).first(4)), "0A 00 00 01");
    EXPECT_EQ(test::to_hex(std::span(s.dst_ip).first(4)), "0A 00 00 02");
    EXPECT_EQ(s.src_port, 40001);
    EXPECT_EQ(s.dst_port, 502);
    EXPECT_EQ(s.seq, 100U);
    EXPECT_EQ(s.flags, 0x18);
    EXPECT_EQ(test::to_hex(s.payload), "00 01 00 00 00 06 01 03 00 64 00 0A");
}

TEST(PcapLearn, ClassicLittleEndianEthernet) {
    expect_normal_facts(learned(
        classic(false, 1,
                framed(normal_traffic().packets(), [](const Bytes& ip) { return ethernet(ip); }))));
}

TEST(PcapLearn, ClassicBigEndianRawIpNanoseconds) {
    expect_normal_facts(learned(classic(true, 101, normal_traffic().packets(), true)));
    expect_normal_facts(learned(classic(false, 228, normal_traffic().packets(), true)));
}

TEST(PcapLearn, PcapngEnhancedAndSimplePacketsBothByteOrders) {
    const auto packets = normal_traffic().packets();
    expect_normal_facts(learned(pcapng(false, 101, packets)));
    expect_normal_facts(learned(pcapng(true, 101, packets)));
    expect_normal_facts(learned(pcapng(false, 101, packets, true)));
    // Two sections: the second, big-endian, with an interface of its own.
    Bytes two = pcapng(false, 276, {});
    append(two, pcapng(true, 101, packets));
    expect_normal_facts(learned(two));
}

TEST(PcapLearn, LinuxCookedCaptures) {
    // SLL: packet type, ARPHRD, address length and 8 address bytes, then the protocol.
    expect_normal_facts(
        learned(classic(false, 113, framed(normal_traffic().packets(), [](const Bytes& ip) {
                            Bytes out =
                                hex("0000 0304 0006 "
                                    "000000000000 0000 0800");
                            append(out, ip);
                            return out;
                        }))));
    // SLL2: the protocol first, then reserved, interface index, ARPHRD, type, address.
    expect_normal_facts(
        learned(pcapng(false, 276, framed(normal_traffic().packets(), [](const Bytes& ip) {
                           Bytes out =
                               hex("0800 0000 00000001 0304 00 06 "
                                   "0000000000000000");
                           append(out, ip);
                           return out;
                       }))));
    // BSD loopback: the address family in the capturing host's order.
    expect_normal_facts(
        learned(classic(false, 0, framed(normal_traffic().packets(), [](const Bytes& ip) {
                            Bytes out = hex("02000000");
                            append(out, ip);
                            return out;
                        }))));
}

TEST(PcapLearn, VlanTaggedEthernet) {
    expect_normal_facts(
        learned(classic(false, 1, framed(normal_traffic().packets(), [](const Bytes& ip) {
                            // 802.1ad outer, 802.1Q inner.
                            return ethernet(ip, hex("88A8 0064 8100 00C8"));
                        }))));
}

Talk ipv6_traffic(Bytes extension, std::uint8_t type) {
    Talk talk(true, std::move(extension), type);
    talk.open()
        .ask(hex("0001 0000 0006 01 03 0064 000A"))
        .answer(hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000"));
    return talk;
}

TEST(PcapLearn, Ipv6WithAndWithoutExtensionHeaders) {
    for (const Bytes& extension : {Bytes{}, hex("06 00 0104 00000000")}) {
        const auto recon = learned(pcapng(false, 1,
                                          framed(ipv6_traffic(extension, 0).packets(),
                                                 [](const Bytes& ip) { return ethernet(ip); })));
        EXPECT_EQ(recon.check_address, 100);
        EXPECT_EQ(recon.max_read, 10);
    }
    // A fragment header is not followed: nothing learned, and it says so.
    const auto capture =
        read_pcap(classic(false, 101, ipv6_traffic(hex("06 00 0000 00000001"), 44).packets()));
    ASSERT_TRUE(capture);
    EXPECT_EQ(capture->packets, 4U);
    EXPECT_TRUE(capture->segments.empty());
}

TEST(PcapLearn, Ipv4FragmentsAndOptionsAndOtherProtocols) {
    const Bytes request = tcp(kClientPort, kPort, 1, 0x18, hex("0001 0000 0006 01 03 0064 000A"));
    // A later fragment, and a UDP datagram: skipped.
    Bytes udp = ipv4(hex("0A000001"), hex("0A000002"), request);
    udp[9] = 17;
    const auto skipped = read_pcap(
        classic(false, 101, {ipv4(hex("0A000001"), hex("0A000002"), request, 0x2001), udp}));
    ASSERT_TRUE(skipped);
    EXPECT_EQ(skipped->packets, 2U);
    EXPECT_TRUE(skipped->segments.empty());
    // Options: a 24-byte header (IHL 6) with one NOP option and padding.
    Bytes with_options = hex("4600 0000 0001 4000 4006 0000 0A000001 0A000002 01000000");
    append(with_options, request);
    with_options[3] = static_cast<std::uint8_t>(with_options.size());
    // Ethernet pads short frames: the IP total length ends the payload before the padding.
    append(with_options, hex("00000000"));
    const auto read = read_pcap(classic(false, 101, {with_options}));
    ASSERT_TRUE(read);
    ASSERT_EQ(read->segments.size(), 1U);
    EXPECT_EQ(test::to_hex(read->segments[0].payload), "00 01 00 00 00 06 01 03 00 64 00 0A");
}

// The same segment twice, and a later retransmission overlapping what came: counted once.
TEST(PcapLearn, RetransmittedBytesAreDropped) {
    Talk talk;
    talk.open()
        .ask(hex("0001 0000 0006 01 03 0064 000A"))
        .at(true, 0, hex("0001 0000 0006 01 03 0064 000A"))
        .answer(hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000"))
        .ask(hex("0002 0000 0006 01 03 0000 0001"))
        // Overlaps the end of the first request and the start of the second.
        .at(true, 6, hex("01 03 0064 000A 0002 0000"))
        .answer(hex("0002 0000 0005 01 03 02 0000"));
    expect_learned(classic(false, 101, talk.packets()), "2 requests, 2 answers",
                   Table::HoldingRegisters, "0-0 100-109 ");
}

// Segments captured in another order than sent are put back in sequence order.
TEST(PcapLearn, OutOfOrderSegmentsAreReordered) {
    Talk talk;
    talk.open()
        .at(true, 12, hex("0002 0000 0006 01 03 0000 0001"))
        .at(true, 0, hex("0001 0000 0006 01 03 0064 000A"))
        .at(false, 29, hex("0002 0000 0005 01 03 02 0000"))
        .at(false, 0, hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000"));
    expect_learned(pcapng(false, 101, talk.packets()), "2 requests, 2 answers",
                   Table::HoldingRegisters, "0-0 100-109 ");
}

// A frame in three segments, and two frames in one.
TEST(PcapLearn, FramesSplitAndJoinedAcrossSegments) {
    Talk talk;
    talk.open()
        .ask(hex("0001 0000"))
        .ask(hex("0006 01 03"))
        .ask(hex("0064 000A 0002 0000 0006 01 01 0000 0008"))
        .answer(hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000 0002"))
        .answer(hex("0000 0004 01 01 01 00"));
    expect_learned(classic(true, 101, talk.packets()), "2 requests, 2 answers", Table::Coils,
                   "0-7 ");
}

// A direction stops at a gap: the request after a lost segment is not learned.
TEST(PcapLearn, AGapStopsTheDirection) {
    Talk talk;
    talk.open()
        .ask(hex("0001 0000 0006 01 03 0064 000A"))
        .answer(hex("0001 0000 0017 01 03 14 0000000000000000000000000000000000000000"))
        .at(true, 24, hex("0003 0000 0006 01 03 0000 0001"))
        .at(false, 29, hex("0002 0000 0005 01 03 02 0000 0003 0000 0005 01 03 02 0000"));
    expect_learned(classic(false, 101, talk.packets()), "1 requests, 1 answers",
                   Table::HoldingRegisters, "100-109 ");
}

// Several units: the most answered with an FC 03 read is the one checked; 0 and 255 answered.
TEST(PcapLearn, UnitsAndTheBroadcastAddresses) {
    Talk talk;
    talk.open()
        .ask(hex("0001 0000 0006 11 03 0005 0003"))
        .answer(hex("0001 0000 0009 11 03 06 000000000000"))
        .ask(hex("0002 0000 0006 11 03 0004 0001"))
        .answer(hex("0002 0000 0005 11 03 02 0000"))
        .ask(hex("0003 0000 0006 01 03 0000 0001"))
        .answer(hex("0003 0000 0005 01 03 02 0000"))
        .ask(hex("0004 0000 0006 FF 03 0000 0001"))
        .answer(hex("0004 0000 0005 FF 03 02 0000"))
        // Unit 0: a write, answered (a gateway's own registers).
        .ask(hex("0005 0000 0006 00 06 0000 0001"))
        .answer(hex("0005 0000 0006 00 06 0000 0001"))
        // An answer to a request never sent is not counted.
        .answer(hex("0009 0000 0005 11 03 02 0000"));
    const auto recon = learned(classic(false, 101, talk.packets()));
    EXPECT_EQ(recon.unit, 0x11);
    EXPECT_EQ(recon.check_address, 4);
    EXPECT_EQ(recon.max_read, 3);
    EXPECT_TRUE(recon.answers_unit_0);
    EXPECT_TRUE(recon.answers_unit_255);
    EXPECT_EQ(ranges_of(recon, Table::HoldingRegisters), "4-7 ");
    EXPECT_EQ(recon.source, "learned from normal.pcap (5 requests, 5 answers)");
}

// Traffic to another port is not the target's; a capture without a read answered with data says
// so in one line.
TEST(PcapLearn, NoReadAnsweredIsOneLine) {
    const Bytes file = classic(false, 101, normal_traffic().packets());
    const auto capture = read_pcap(file);
    ASSERT_TRUE(capture);
    const auto other_port = learn_recon(*capture, 1502, "normal.pcap");
    ASSERT_FALSE(other_port);
    EXPECT_EQ(other_port.error(),
              "normal.pcap: no FC 03 read answered in 0 Modbus/TCP requests to port 1502: nothing "
              "to check liveness with");
    Talk talk;
    talk.open()
        .ask(hex("0001 0000 0006 01 03 0064 000A"))
        .answer(hex("0001 0000 0003 01 83 02"))
        .ask(hex("0002 0000 0006 01 04 0000 0001"))
        .answer(hex("0002 0000 0005 01 04 02 0000"));
    const auto refused =
        learn_recon(*read_pcap(classic(false, 101, talk.packets())), 502, "x.pcap");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error(),
              "x.pcap: no FC 03 read answered in 2 Modbus/TCP requests to port 502: nothing to "
              "check liveness with");
}

TEST(PcapReader, BadAndTruncatedFilesNameTheOffset) {
    const Bytes good_classic = classic(false, 101, normal_traffic().packets());
    const Bytes good_pcapng = pcapng(false, 101, normal_traffic().packets());
    const auto error_of = [](const Bytes& file) {
        const auto read = read_pcap(file);
        return read ? std::string("no error") : read.error();
    };
    EXPECT_EQ(error_of(hex("0102")), "not a pcap or pcapng file: fewer than 4 bytes at offset 0");
    EXPECT_EQ(error_of(hex("7B226122 3A20317D")),
              "not a pcap or pcapng file: magic 7B226122 at offset 0");
    EXPECT_EQ(error_of(Bytes(good_classic.begin(), good_classic.begin() + 20)),
              "pcap header cut short at offset 20");
    EXPECT_EQ(error_of(Bytes(good_classic.begin(), good_classic.begin() + 30)),
              "pcap packet record header cut short at offset 24");
    // The first record: 40 bytes of SYN (IPv4 20 + TCP 20) after its 16-byte header.
    EXPECT_EQ(error_of(Bytes(good_classic.begin(), good_classic.begin() + 70)),
              "pcap packet at offset 24 claims 40 bytes, 30 remain");
    EXPECT_EQ(error_of(Bytes(good_pcapng.begin(), good_pcapng.begin() + 30)),
              "pcapng block header cut short at offset 28");
    EXPECT_EQ(error_of(Bytes(good_pcapng.begin(), good_pcapng.begin() + 40)),
              "pcapng block at offset 28 claims 20 bytes, 12 remain");
    EXPECT_EQ(error_of(Bytes(good_pcapng.begin(), good_pcapng.end() - 2)).substr(0, 20),
              "pcapng block at offs");
    Bytes bad_length = good_pcapng;
    bad_length[4] = 13;
    EXPECT_EQ(error_of(bad_length), "pcapng block at offset 0 has length 13");
    Bytes no_magic = good_pcapng;
    no_magic[8] = 0;
    EXPECT_EQ(error_of(no_magic), "pcapng section header at offset 0 has no byte-order magic");
    // A packet block before any interface block.
    Bytes no_interface = pcapng(false, 101, {});
    const Bytes shb(no_interface.begin(), no_interface.begin() + 28);
    Bytes orphan = shb;
    Bytes epb = hex("00000000 0000000000000000 04000000 04000000 45000000");
    append(orphan, block(false, 6, epb));
    EXPECT_EQ(error_of(orphan),
              "pcapng packet block at offset 28 names interface 0, not described");
    // Every cut of a good file is an error or a shorter capture, never a crash.
    for (std::size_t size = 0; size < good_pcapng.size(); ++size)
        (void)read_pcap(std::span(good_pcapng).first(size));
}

}  // namespace
}  // namespace mblab::robustness
