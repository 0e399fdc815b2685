#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "client/link_types.hpp"
#include "conformance/provenance.hpp"

namespace mblab::conformance {

// Everything the tester's connections carried, in order, for a pcap file.
struct CaptureEvent {
    enum class Kind : std::uint8_t { Open, Sent, Received, Close };
    Kind kind = Kind::Open;
    std::chrono::system_clock::time_point time;
    std::vector<std::uint8_t> bytes;  // Sent, Received
    client::LinkAddresses addresses;  // Open
    bool by_peer = false;             // Close
    // What the traffic was for when the event came ("case 7.3.1"): each packet's comment.
    std::string label = {};
};

// With a bound, only the last part of a long run is kept: a robustness run against a device that
// floods its answers would otherwise keep every byte of it (hundreds of megabytes), and the frames
// before a finding are the ones worth having. What is let go goes a connection at a time, so
// what is kept starts where a connection opens.
class Capture : public client::LinkObserver {
  public:
    // `bound`: roughly the memory the kept events may take, in bytes; 0 keeps everything.
    explicit Capture(std::size_t bound = 0) : bound_(bound) {}

    void on_open(const client::LinkAddresses& addresses) override;
    void on_sent(std::span<const std::uint8_t> bytes) override;
    void on_received(std::span<const std::uint8_t> bytes) override;
    void on_close(bool by_peer) override;
    void on_label(std::string_view label) override { label_ = label; }

    const std::vector<CaptureEvent>& events() const { return events_; }
    // The bytes sent and received that were let go to keep within the bound.
    std::size_t dropped_bytes() const { return dropped_bytes_; }

  private:
    void keep(CaptureEvent event);

    std::size_t bound_ = 0;
    std::size_t kept_ = 0;  // the memory events_ takes, as keep() counts it
    std::size_t dropped_bytes_ = 0;
    std::string label_;
    std::vector<CaptureEvent> events_;
};

// Writes the capture as pcapng: a section header whose shb_userappl names mblab and its commit,
// shb_hardware and shb_os the tester's machine, and whose comment holds the provenance lines
// (classic pcap has no place for them); then raw IPv4 or IPv6 (LINKTYPE_RAW) packets, each with
// its event's label as its comment (opt_comment), as the connection was: each connection
// opens with a three-way handshake and ends with FINs, segments hold whole MBAP frames (a partial
// frame is written when the other side speaks or the connection closes), sequence and
// acknowledgement numbers follow the bytes, and the device's side is port 502 whatever port it
// really used, so Wireshark decodes Modbus/TCP. False with `error` set when the file cannot be
// written.
bool write_pcap(const std::string& path, const std::vector<CaptureEvent>& events,
                const Provenance& provenance, std::string& error);

// A serial line's capture (RTU or ASCII, RTU over TCP too) as pcapng: the same section header,
// then each frame as it was written or read, marked outbound (tester) or inbound (device), its
// label as its comment, on a private-use link type, since none is assigned to Modbus serial
// lines: RTU frames on LINKTYPE_USER0 (147), which Wireshark decodes once User 0 is mapped to
// "mbrtu" (docs/robustness.md says how); ASCII frames, their text from ':' to CR LF, on
// LINKTYPE_USER1 (148), which no Modbus dissector reads, so they show as text.
bool write_line_pcap(const std::string& path, const std::vector<CaptureEvent>& events,
                     client::Framing framing, const Provenance& provenance, std::string& error);

// write_pcap for Modbus/TCP, write_line_pcap for a line's framing.
bool write_capture(const std::string& path, const std::vector<CaptureEvent>& events,
                   client::Framing framing, const Provenance& provenance, std::string& error);

}  // namespace mblab::conformance
