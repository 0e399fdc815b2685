// The pcap reader by hand: one classic file written out byte by byte, and bad or truncated files
// refused with the offset of what is wrong.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capture_builder.hpp"

namespace mblab::robustness {
namespace {

using namespace capture_test;

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
