#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "protocol/adu.hpp"

// The vocabulary every link speaks, whatever carries its bytes: what came back, what went wrong,
// and who watches the traffic.
namespace mblab::client {

using Framing = protocol::Framing;

struct LinkError {
    std::string message;  // "connection refused", "timeout after 2000 ms", ...
    // The TLS handshake failed after the server took part in it: it sent an alert, closed the
    // connection, or sent what this side refused. Unset when the connection failed, the server
    // said nothing before the deadline, or this side gave up before hearing from it.
    bool tls_refused = false;
};

// Both ends of a connection. Addresses are in network order: the first 4 bytes of an IPv4
// address, all 16 of an IPv6 one; all zero when unknown.
struct LinkAddresses {
    bool ipv6 = false;
    std::array<std::uint8_t, 16> local_ip{};
    std::uint16_t local_port = 0;
    std::array<std::uint8_t, 16> peer_ip{};
    std::uint16_t peer_port = 0;
};

// Watches traffic for captures (pcap); every callback sees the bytes as they crossed the socket.
class LinkObserver {
  public:
    virtual ~LinkObserver() = default;
    virtual void on_open(const LinkAddresses& addresses) = 0;
    virtual void on_sent(std::span<const std::uint8_t> bytes) = 0;
    virtual void on_received(std::span<const std::uint8_t> bytes) = 0;
    // `by_peer` is true when the device closed or reset the connection first.
    virtual void on_close(bool by_peer) = 0;
    // Names what the traffic from now on is for (a conformance case: "case 7.3.1"; empty for
    // nothing in particular), for a capture to note beside its packets.
    virtual void on_label(std::string_view /*label*/) {}
};

enum class ReceiveStatus : std::uint8_t {
    Frame,      // `bytes` holds one whole frame
    Timeout,    // nothing, or only part of a frame (in `bytes`), before the deadline
    Closed,     // the peer closed or reset; `bytes` holds any partial frame
    Malformed,  // the bytes cannot be a frame (a length field that describes none, a bad CRC);
                // `bytes` holds what came
};

struct Received {
    Received() = default;
    Received(ReceiveStatus status_, std::vector<std::uint8_t> bytes_ = {}, std::string detail_ = {})
        : status(status_), bytes(std::move(bytes_)), detail(std::move(detail_)) {}

    ReceiveStatus status = ReceiveStatus::Timeout;
    std::vector<std::uint8_t> bytes;  // as they came over the link
    std::string detail;               // why, for Closed and Malformed
    std::size_t discarded = 0;        // bytes that came after `bytes` and were counted, not kept
    // For a Frame: its header and PDU, as the link's framer read them.
    protocol::AduHeader header{};
    std::vector<std::uint8_t> pdu;
    // For a Frame on a lenient link: what a strict framer would refuse in it (a protocol id
    // other than 0, an MBAP length of 1); empty when it is clean.
    std::string violation;
    // On a serial line: the longest silence between two reads of this frame's bytes.
    std::chrono::microseconds largest_gap{0};
};

}  // namespace mblab::client
