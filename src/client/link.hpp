#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include "client/link_types.hpp"
#include "security/tls_channel.hpp"

// The seam between the client's transactions and a transport. A link moves whole ADUs: it sends
// the bytes it is given and hands back one frame at a time, cut by its own framing rules. How a
// PDU is wrapped for it (MBAP header, RTU CRC, ASCII hex and LRC) depends on framing(), so a new
// transport plugs in by implementing this interface and naming its framing.
namespace mblab::client {

class Link {
  public:
    virtual ~Link() = default;

    virtual Framing framing() const = 0;
    // "tcp://127.0.0.1:502": what the user names in messages.
    virtual const std::string& name() const = 0;
    virtual bool is_open() const = 0;
    // Writes a whole ADU. False with `error` set when the link is gone.
    virtual bool send(std::span<const std::uint8_t> adu, LinkError& error) = 0;
    // One whole frame in the link's framing, or why none came before `timeout`.
    virtual Received receive_frame(std::chrono::milliseconds timeout) = 0;
    // Whatever the device sends within `timeout` that nobody asked for: raw bytes on a TCP link
    // (the first kilobytes kept, the rest counted), a frame or a framing error on a line.
    virtual Received receive_any(std::chrono::milliseconds timeout) = 0;
    virtual void close() = 0;
    // The TLS session of an mbaps:// link once it is up; nullptr for other links.
    virtual const security::TlsPeer* tls_peer() const { return nullptr; }
};

}  // namespace mblab::client
