#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/frame_reader.hpp"
#include "client/link_types.hpp"
#include "protocol/result.hpp"
#include "security/tls_channel.hpp"
#include "transport/channel.hpp"
#include "transport/tls_stream.hpp"

// A blocking TCP link that puts any bytes on the wire and takes whole MBAP frames off it. The
// conformance tester judges what devices send, so its framer is lenient: a wrong protocol id or
// unit id still arrives as a frame for the tester to mark.
namespace mblab::client {

// Modbus/TCP Security (mbaps://): the TLS context a link's handshake uses, and the name the
// server's certificate must carry.
struct TlsSetup {
    security::SharedContext context;
    std::string server_name;
};

struct Endpoint {
    std::string host;
    std::uint16_t port = 502;
    std::shared_ptr<const TlsSetup> tls{};  // set: MBAP inside TLS
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
    // The TLS session of an mbaps:// link (nullptr on plain TCP): version, cipher, peer.
    const security::TlsChannel* tls() const { return tls_ ? &tls_->session() : nullptr; }
    // The last alert the server sent, kept after the link closed on it.
    const security::TlsAlert& tls_alert() const { return alert_; }
    // Asks for a TLS renegotiation (a key update on TLS 1.3) and sends the request; false when
    // the session could not ask. How the server took it shows in the next receive.
    bool renegotiate(LinkError& error);
    // Sends close_notify and waits up to `timeout` for the server to end the session: true when it
    // answered with its close_notify or closed the connection, false when it kept it open.
    bool close_notify(std::chrono::milliseconds timeout, std::string& how);
    const LinkAddresses& addresses() const { return addresses_; }

    // Writes every byte in one call sequence (one TCP segment for small writes, Nagle is off).
    // Returns false with `error` set when the connection is gone.
    bool send(std::span<const std::uint8_t> bytes, LinkError& error);

    // Waits until one MBAP frame is complete, the deadline passes, or the peer closes. Bytes past
    // the frame stay buffered for the next call, so pipelined answers are taken one at a time.
    Received receive_frame(std::chrono::milliseconds timeout);
    // As receive_frame(), but on timeout the part of a frame already come stays buffered.
    Received next_frame(std::chrono::milliseconds timeout);

    // Reads whatever arrives for `timeout` (or until the peer closes); used to check a device
    // stays silent. A device that floods is not allowed to fill memory: the first
    // kKeptUnasked bytes are kept, the rest only counted in `discarded`.
    Received receive_any(std::chrono::milliseconds timeout);
    static constexpr std::size_t kKeptUnasked = 4096;

    void close();

    // Writes what the peer takes before `timeout` passes (plain TCP; over TLS, send()). The count
    // of bytes written; the link is dropped only when the peer is gone.
    std::size_t send_for(std::span<const std::uint8_t> bytes, std::chrono::milliseconds timeout,
                         LinkError& error);
    // Closes the socket in TCP repair mode, so no FIN or reset leaves: the peer keeps a half-open
    // connection. Needs CAP_NET_ADMIN; false, and the link still open, without it.
    bool vanish();
    int descriptor() const { return fd_; }
    // Whether vanish() is allowed here (the capability, asked of a socket of our own).
    static bool can_vanish();

  private:
    RawLink(int fd, const LinkAddresses& addresses, LinkObserver* observer);
    // The TLS handshake on a connected socket, bounded by the deadline; "" when it succeeded.
    std::string handshake(const TlsSetup& setup, std::chrono::steady_clock::time_point deadline);
    // Writes every byte, and the TLS records held back, waiting for room as long as it takes;
    // false with `error` set when the connection is gone.
    bool send_all(std::span<const std::uint8_t> bytes, std::string& error);

    // Reads once from the socket into the buffer.
    enum class Fill : std::uint8_t { Data, Timeout, Closed };
    // One read of the channel (through TLS on mbaps://) into `chunk`.
    Fill read_plain(std::string& detail, std::span<std::uint8_t> chunk, std::size_t& got);
    // Waits for bytes until the deadline and reads once into `chunk` (`got` bytes).
    Fill read_some(std::chrono::steady_clock::time_point deadline, std::string& detail,
                   std::span<std::uint8_t> chunk, std::size_t& got);
    // read_some() into the frame reader.
    Fill fill(std::chrono::steady_clock::time_point deadline, std::string& detail);
    // Waits for more bytes: nothing when some came, the final outcome on timeout or close.
    std::optional<Received> wait(std::chrono::steady_clock::time_point deadline);
    void drop(bool by_peer);

    int fd_ = -1;  // the socket, for poll(); the channel owns it
    // The socket, or TLS over it (then tls_ points into it).
    std::unique_ptr<transport::Channel> channel_;
    transport::TlsStream* tls_ = nullptr;
    LinkAddresses addresses_;
    LinkObserver* observer_ = nullptr;
    security::TlsAlert alert_;
    bool handshake_heard_ = false;  // the server sent bytes or closed during the handshake
    FrameReader reader_{{.framing = Framing::Mbap, .lenient = true}};
};

}  // namespace mblab::client
