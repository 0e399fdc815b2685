#pragma once

#include <chrono>
#include <cstddef>
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
    // As receive_frame(), but a frame only part come by `timeout` stays for the next call rather
    // than being handed back: for reading answers while more requests are still being written.
    virtual Received next_frame(std::chrono::milliseconds timeout) {
        return receive_frame(timeout);
    }
    // Whatever the device sends within `timeout` that nobody asked for: raw bytes on a TCP link
    // (the first kilobytes kept, the rest counted), a frame or a framing error on a line.
    virtual Received receive_any(std::chrono::milliseconds timeout) = 0;
    virtual void close() = 0;
    // Writes what the device takes before `timeout` passes, and no more: a device that stops
    // reading must not stall the writer (the robustness tester's slow reader and flood). The
    // count of bytes written; the link stays open unless the device closed it.
    // A serial line takes bytes at its own pace, never stalled by the device: plain send().
    virtual std::size_t send_for(std::span<const std::uint8_t> bytes,
                                 std::chrono::milliseconds /*timeout*/, LinkError& error) {
        return send(bytes, error) ? bytes.size() : 0;
    }
    // Lets the connection go without a FIN or a reset, as a client that lost power does: the
    // device is left holding a half-open connection. False (the link unchanged) where the system
    // does not allow it.
    virtual bool vanish() { return false; }
    // The TCP socket under the link, for asking the kernel about the connection (when data last
    // arrived); -1 where there is none (a serial line, a closed link).
    virtual int tcp_descriptor() const { return -1; }
    // The TLS session of an mbaps:// link once it is up; nullptr for other links.
    virtual const security::TlsPeer* tls_peer() const { return nullptr; }
};

}  // namespace mblab::client
