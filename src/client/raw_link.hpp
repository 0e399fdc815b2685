#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "protocol/result.hpp"

// A blocking TCP link that puts any bytes on the wire and takes whole MBAP frames off it. The
// conformance tester judges what devices send, so frames are split by their length field alone:
// a wrong protocol id or unit id still arrives as a frame for the tester to mark.
namespace mblab::client {

struct Endpoint {
    std::string host;
    std::uint16_t port = 502;
};

struct LinkError {
    std::string message;  // "connection refused", "timeout after 2000 ms", ...
};

// Both ends of a connection; IPv4 addresses in host order, 0 for IPv6.
struct LinkAddresses {
    std::uint32_t local_ip = 0;
    std::uint16_t local_port = 0;
    std::uint32_t peer_ip = 0;
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
};

enum class ReceiveStatus : std::uint8_t {
    Frame,      // `bytes` holds one whole frame
    Timeout,    // nothing, or only part of a frame (in `bytes`), before the deadline
    Closed,     // the peer closed or reset; `bytes` holds any partial frame
    Malformed,  // the header's length field cannot describe a frame; `bytes` holds what came
};

struct Received {
    ReceiveStatus status = ReceiveStatus::Timeout;
    std::vector<std::uint8_t> bytes;
    std::string detail;         // why, for Closed and Malformed
    std::size_t discarded = 0;  // bytes that came after `bytes` and were counted, not kept
};

class RawLink {
  public:
    static protocol::Result<RawLink, LinkError> connect(const Endpoint& endpoint,
                                                        std::chrono::milliseconds timeout,
                                                        LinkObserver* observer = nullptr);

    RawLink(RawLink&& other) noexcept;
    RawLink& operator=(RawLink&& other) noexcept;
    RawLink(const RawLink&) = delete;
    RawLink& operator=(const RawLink&) = delete;
    ~RawLink();

    bool is_open() const { return fd_ >= 0; }
    const LinkAddresses& addresses() const { return addresses_; }

    // Writes every byte in one call sequence (one TCP segment for small writes, Nagle is off).
    // Returns false with `error` set when the connection is gone.
    bool send(std::span<const std::uint8_t> bytes, LinkError& error);

    // Waits until one MBAP frame is complete, the deadline passes, or the peer closes. Bytes past
    // the frame stay buffered for the next call, so pipelined answers are taken one at a time.
    Received receive_frame(std::chrono::milliseconds timeout);

    // Reads whatever arrives for `timeout` (or until the peer closes); used to check a device
    // stays silent. A device that floods is not allowed to fill memory: the first
    // kKeptUnasked bytes are kept, the rest only counted in `discarded`.
    Received receive_any(std::chrono::milliseconds timeout);
    static constexpr std::size_t kKeptUnasked = 4096;

    void close();

  private:
    RawLink(int fd, const LinkAddresses& addresses, LinkObserver* observer);
    // Reads once from the socket into the buffer.
    enum class Fill : std::uint8_t { Data, Timeout, Closed };
    Fill fill(std::chrono::steady_clock::time_point deadline, std::string& detail);
    // Waits for more bytes: nothing when some came, the final outcome on timeout or close.
    std::optional<Received> wait(std::chrono::steady_clock::time_point deadline);
    Received take(ReceiveStatus status, std::size_t count, std::string detail = {});
    void drop(bool by_peer);

    int fd_ = -1;
    LinkAddresses addresses_;
    LinkObserver* observer_ = nullptr;
    std::vector<std::uint8_t> buffer_;
};

// Size of a whole MBAP frame whose first bytes are `head`: 0 when more header bytes are needed,
// -1 when the length field cannot be right (0, or more than a 260-byte ADU allows).
long mbap_frame_size(std::span<const std::uint8_t> head);

}  // namespace mblab::client
