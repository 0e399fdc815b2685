// What the learner makes of reassembled Modbus/TCP traffic: every link type and file format the
// reader takes, TCP reassembly (retransmissions, reordering, frames split and joined, gaps), units.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capture_builder.hpp"

namespace mblab::robustness {
namespace {

using namespace capture_test;

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

}  // namespace
}  // namespace mblab::robustness
