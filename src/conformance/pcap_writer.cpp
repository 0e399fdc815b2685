#include <fmt/core.h>
#include <sys/utsname.h>

#include <array>
#include <optional>

#include "conformance/capture.hpp"
#include "conformance/pcap_format.hpp"
#include "conformance/reports.hpp"
#include "protocol/framer.hpp"

namespace mblab::conformance {

namespace {

using namespace pcap;

constexpr std::uint16_t kModbusPort = 502;
constexpr std::array<std::uint8_t, 16> kLoopback4{127, 0, 0, 1};
constexpr std::array<std::uint8_t, 16> kLoopback6{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
constexpr std::size_t kIp4Header = 20;
constexpr std::size_t kIp6Header = 40;
constexpr std::size_t kTcpHeader = 20;

void put16(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t value) {
    out[at] = static_cast<std::uint8_t>(value >> 8);
    out[at + 1] = static_cast<std::uint8_t>(value);
}

void put32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t value) {
    put16(out, at, value >> 16);
    put16(out, at + 2, value & 0xFFFF);
}

std::uint32_t sum16(const std::uint8_t* bytes, std::size_t size, std::uint32_t sum = 0) {
    for (std::size_t i = 0; i + 1 < size; i += 2)
        sum += (bytes[i] << 8) | bytes[i + 1];
    if (size % 2 != 0) sum += bytes[size - 1] << 8;
    return sum;
}

std::uint16_t fold(std::uint32_t sum) {
    while (sum >> 16)
        sum = (sum & 0xFFFF) + (sum >> 16);
    return static_cast<std::uint16_t>(~sum);
}

struct Peer {
    std::array<std::uint8_t, 16> ip{};  // the first 4 bytes for IPv4
    std::uint16_t port = 0;
    std::uint32_t next_seq = 0;  // sequence number of the next byte this side sends
};

// One TCP connection's packets: the client is the tester, the server the device.
class Stream {
  public:
    Stream(const client::LinkAddresses& addresses, std::uint32_t index) : ipv6_(addresses.ipv6) {
        const auto& loopback = ipv6_ ? kLoopback6 : kLoopback4;
        constexpr std::array<std::uint8_t, 16> kUnknown{};
        client_.ip = addresses.local_ip != kUnknown ? addresses.local_ip : loopback;
        client_.port = addresses.local_port != 0 ? addresses.local_port
                                                 : static_cast<std::uint16_t>(40000 + index);
        server_.ip = addresses.peer_ip != kUnknown ? addresses.peer_ip : loopback;
        server_.port = kModbusPort;
        // Distinct, recognisable initial sequence numbers per connection.
        client_.next_seq = 0x10000000U * (index % 8 + 1);
        server_.next_seq = 0x80000000U + 0x01000000U * (index % 8);
    }

    template <class Emit>
    void open(Emit&& emit) {
        emit(packet(client_, server_, kTcpSyn, {}, false));
        client_.next_seq += 1;
        emit(packet(server_, client_, kTcpSyn | kTcpAck, {}, true));
        server_.next_seq += 1;
        emit(packet(client_, server_, kTcpAck, {}, true));
    }

    std::vector<std::uint8_t> data(bool from_client, std::span<const std::uint8_t> bytes) {
        Peer& from = from_client ? client_ : server_;
        Peer& to = from_client ? server_ : client_;
        auto out = packet(from, to, kTcpPsh | kTcpAck, bytes, true);
        from.next_seq += static_cast<std::uint32_t>(bytes.size());
        return out;
    }

    template <class Emit>
    void close(bool by_server, Emit&& emit) {
        Peer& first = by_server ? server_ : client_;
        Peer& second = by_server ? client_ : server_;
        emit(packet(first, second, kTcpFin | kTcpAck, {}, true));
        first.next_seq += 1;
        emit(packet(second, first, kTcpFin | kTcpAck, {}, true));
        second.next_seq += 1;
        emit(packet(first, second, kTcpAck, {}, true));
    }

  private:
    std::vector<std::uint8_t> packet(const Peer& from, const Peer& to, std::uint8_t flags,
                                     std::span<const std::uint8_t> payload, bool ack) {
        const std::size_t tcp_size = kTcpHeader + payload.size();
        const std::size_t t = ipv6_ ? kIp6Header : kIp4Header;
        std::vector<std::uint8_t> out(t + tcp_size, 0);
        // The TCP checksum's pseudo-header: both addresses, the protocol and the segment's length.
        std::uint32_t pseudo = kTcp + static_cast<std::uint32_t>(tcp_size);
        if (ipv6_) {
            out[0] = 0x60;  // IPv6, traffic class and flow label 0
            put16(out, 4, static_cast<std::uint32_t>(tcp_size));
            out[6] = kTcp;
            out[7] = 64;  // hop limit
            std::copy(from.ip.begin(), from.ip.end(), out.begin() + 8);
            std::copy(to.ip.begin(), to.ip.end(), out.begin() + 24);
            pseudo = sum16(out.data() + 8, 32, pseudo);
        } else {
            out[0] = 0x45;  // IPv4, 20-byte header
            put16(out, 2, static_cast<std::uint32_t>(out.size()));
            put16(out, 4, ip_id_++);
            put16(out, 6, 0x4000);  // don't fragment
            out[8] = 64;            // TTL
            out[9] = kTcp;
            std::copy_n(from.ip.begin(), 4, out.begin() + 12);
            std::copy_n(to.ip.begin(), 4, out.begin() + 16);
            put16(out, 10, fold(sum16(out.data(), kIp4Header)));
            pseudo = sum16(out.data() + 12, 8, pseudo);
        }

        put16(out, t, from.port);
        put16(out, t + 2, to.port);
        put32(out, t + 4, from.next_seq);
        put32(out, t + 8, ack ? to.next_seq : 0);
        out[t + 12] = 5 << 4;  // 20-byte header
        out[t + 13] = flags;
        put16(out, t + 14, 65535);  // window
        std::copy(payload.begin(), payload.end(), out.begin() + static_cast<long>(t + kTcpHeader));
        put16(out, t + 16, fold(sum16(out.data() + t, tcp_size, pseudo)));
        return out;
    }

    bool ipv6_;
    Peer client_;
    Peer server_;
    std::uint16_t ip_id_ = 1;
};

// pcapng blocks (draft-ietf-opsawg-pcapng), written little-endian: the byte-order magic of the
// section header tells readers which order the file uses.
class PcapngFile {
  public:
    void section_header(const Provenance& provenance) {
        Block block(out_, kSectionHeader);
        put32(kByteOrderMagic);
        put16(1);  // version 1.0
        put16(0);
        put32(0xFFFFFFFFU);  // section length not given: the file may be cut short
        put32(0xFFFFFFFFU);
        std::string comment;
        for (const auto& line : provenance_lines(provenance))
            comment += line + "\n";
        option(kComment, comment);
        utsname host{};
        if (::uname(&host) == 0) {
            option(kShbHardware, host.machine);
            option(kShbOs, fmt::format("{} {}", host.sysname, host.release));
        }
        option(kShbUserAppl,
               fmt::format("mblab {} (commit {})", provenance.version, provenance.commit));
        end_options();
        block.close();
    }

    void interface(std::uint16_t link_type, std::uint32_t snap_length) {
        Block block(out_, kInterfaceDescription);
        put16(link_type);
        put16(0);
        put32(snap_length);
        // No if_tsresol: the default, microseconds, is what the timestamps are in.
        block.close();
    }

    // `comment`: opt_comment, when not empty. `inbound`: the epb_flags direction, for packets
    // whose link layer does not say it.
    void packet(std::chrono::microseconds since_epoch, std::span<const std::uint8_t> bytes,
                std::string_view comment, std::optional<bool> inbound = std::nullopt) {
        Block block(out_, kEnhancedPacket);
        const auto stamp = static_cast<std::uint64_t>(since_epoch.count());
        put32(0);  // interface 0
        put32(static_cast<std::uint32_t>(stamp >> 32));
        put32(static_cast<std::uint32_t>(stamp));
        put32(static_cast<std::uint32_t>(bytes.size()));
        put32(static_cast<std::uint32_t>(bytes.size()));
        out_.insert(out_.end(), bytes.begin(), bytes.end());
        pad();
        if (!comment.empty()) option(kComment, comment);
        if (inbound) {
            put16(kEpbFlags);
            put16(4);
            put32(*inbound ? 1U : 2U);
        }
        if (!comment.empty() || inbound) end_options();
        block.close();
    }

    const std::string& bytes() const { return out_; }

  private:
    // Writes the type and a length to be filled in; close() writes the length at both ends, as
    // pcapng has it so a reader can walk the blocks backwards too.
    class Block {
      public:
        Block(std::string& out, std::uint32_t type) : out_(out), start_(out.size()) {
            append32(out_, type);
            append32(out_, 0);
        }
        void close() {
            const auto length = static_cast<std::uint32_t>(out_.size() - start_ + 4);
            append32(out_, length);
            for (std::size_t i = 0; i < 4; ++i)
                out_[start_ + 4 + i] = static_cast<char>(length >> (8 * i));
        }

      private:
        std::string& out_;
        std::size_t start_;
    };

    static void append32(std::string& out, std::uint32_t value) {
        for (int i = 0; i < 4; ++i)
            out += static_cast<char>(value >> (8 * i));
    }
    void put16(std::uint16_t value) {
        out_ += static_cast<char>(value);
        out_ += static_cast<char>(value >> 8);
    }
    void put32(std::uint32_t value) { append32(out_, value); }
    void pad() {
        while (out_.size() % 4 != 0)
            out_ += '\0';
    }
    // An option's value is at most 65535 bytes; provenance text is far shorter, and a longer one
    // is cut rather than making the file unreadable.
    void option(std::uint16_t code, std::string_view value) {
        value = value.substr(0, 0xFFFF);
        put16(code);
        put16(static_cast<std::uint16_t>(value.size()));
        out_ += value;
        pad();
    }
    void end_options() {
        put16(kEndOfOptions);
        put16(0);
    }

    std::string out_;
};

constexpr std::uint32_t kSnapLength = 65535;

}  // namespace

bool write_pcap(const std::string& path, const std::vector<CaptureEvent>& events,
                const Provenance& provenance, std::string& error) {
    PcapngFile file;
    file.section_header(provenance);
    file.interface(kLinkRaw, kSnapLength);
    std::optional<Stream> stream;
    std::uint32_t streams = 0;
    // Bytes not yet written as segments, per direction (0: tester, 1: device).
    std::array<std::vector<std::uint8_t>, 2> pending;
    for (const auto& e : events) {
        const auto since_epoch =
            std::chrono::duration_cast<std::chrono::microseconds>(e.time.time_since_epoch());
        auto emit = [&](const std::vector<std::uint8_t>& packet) {
            file.packet(since_epoch, packet, e.label);
        };
        auto flush = [&](std::size_t side, bool whole_frames_only) {
            auto& bytes = pending[side];
            std::size_t cut = bytes.size();
            if (whole_frames_only) {
                cut = 0;
                protocol::Framer framer({.framing = protocol::Framing::Mbap, .lenient = true});
                while (cut < bytes.size()) {
                    std::size_t consumed = 0;
                    const auto event = framer.feed(std::span(bytes).subspan(cut), consumed);
                    if (event.is_error()) {
                        cut = bytes.size();  // not MBAP: nothing to wait for
                        break;
                    }
                    if (!event.is_frame()) break;  // the rest is a frame still arriving
                    cut += consumed;
                }
            }
            if (cut == 0 || !stream) return;
            emit(stream->data(side == 0, std::span(bytes).first(cut)));
            bytes.erase(bytes.begin(), bytes.begin() + static_cast<long>(cut));
        };
        switch (e.kind) {
            case CaptureEvent::Kind::Open:
                stream.emplace(e.addresses, streams++);
                pending = {};
                stream->open(emit);
                break;
            case CaptureEvent::Kind::Sent:
            case CaptureEvent::Kind::Received: {
                // Segments are cut at frame boundaries, as a device or Wireshark sees frames;
                // how the bytes really left the socket is in the report, not here.
                const std::size_t side = e.kind == CaptureEvent::Kind::Sent ? 0 : 1;
                flush(1 - side, false);
                pending[side].insert(pending[side].end(), e.bytes.begin(), e.bytes.end());
                flush(side, true);
                break;
            }
            case CaptureEvent::Kind::Close:
                flush(0, false);
                flush(1, false);
                if (stream) stream->close(e.by_peer, emit);
                stream.reset();
                break;
        }
    }
    return write_text_file(path, file.bytes(), error);
}

bool write_line_pcap(const std::string& path, const std::vector<CaptureEvent>& events,
                     client::Framing framing, const Provenance& provenance, std::string& error) {
    PcapngFile file;
    file.section_header(provenance);
    file.interface(framing == client::Framing::Ascii ? kLinkUser1 : kLinkUser0, kSnapLength);
    for (const auto& e : events) {
        if (e.kind != CaptureEvent::Kind::Sent && e.kind != CaptureEvent::Kind::Received) continue;
        file.packet(
            std::chrono::duration_cast<std::chrono::microseconds>(e.time.time_since_epoch()),
            e.bytes, e.label, e.kind == CaptureEvent::Kind::Received);
    }
    return write_text_file(path, file.bytes(), error);
}

bool write_capture(const std::string& path, const std::vector<CaptureEvent>& events,
                   client::Framing framing, const Provenance& provenance, std::string& error) {
    if (framing == client::Framing::Mbap) return write_pcap(path, events, provenance, error);
    return write_line_pcap(path, events, framing, provenance, error);
}

}  // namespace mblab::conformance
