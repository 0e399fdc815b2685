#pragma once

#include <sys/socket.h>
#include <sys/uio.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace mblab::security {
struct TlsPeer;
}

// One byte channel, the only door bytes take in and out of a connection: a socket, TLS over
// another channel, or an in-memory pair for tests. Every call returns at once with what a
// non-blocking socket would report; waiting for readiness is the owner's (an epoll loop, or
// poll() with a deadline in a blocking client). A channel knows nothing of what the bytes mean.
namespace mblab::transport {

struct Io {
    enum class Status : std::uint8_t {
        Done,        // `bytes` moved (a write may move fewer than it was given)
        WouldBlock,  // nothing to read yet, or no room to write
        EndOfInput,  // the peer ended its side in order (FIN, or TLS close_notify)
        Failed,      // reset, or a TLS failure: `code` holds errno when the descriptor said why
    };
    Status status = Status::Done;
    std::size_t bytes = 0;
    int code = 0;

    static Io done(std::size_t count) { return {Status::Done, count, 0}; }
    static Io would_block() { return {Status::WouldBlock, 0, 0}; }
    static Io end_of_input() { return {Status::EndOfInput, 0, 0}; }
    static Io failed(int code = 0) { return {Status::Failed, 0, code}; }
};

// Who is at the other end: the socket's address (size 0 when the channel has none), and the TLS
// session's peer once a handshake is over.
struct PeerIdentity {
    sockaddr_storage address{};
    socklen_t address_size = 0;
    const security::TlsPeer* tls = nullptr;
};

class Channel {
  public:
    virtual ~Channel() = default;

    // Reads what is there, up to out.size().
    virtual Io read(std::span<std::uint8_t> out) = 0;
    // Writes what fits of the buffers, in order, as one gathered write.
    virtual Io writev(std::span<const iovec> buffers) = 0;
    Io write(std::span<const std::uint8_t> bytes) {
        const iovec one{const_cast<std::uint8_t*>(bytes.data()), bytes.size()};
        return writev({&one, 1});
    }

    // Bytes ready to read without waiting for the descriptor (records TLS has not handed out).
    virtual bool has_input() const { return false; }
    // Whether input may be left after the last read. A socket can only tell that its read filled
    // all the room it had. An owner woken only by new input (an edge) reads again instead of
    // waiting.
    virtual bool input_may_remain() const = 0;
    // Output the channel holds back until the descriptor takes more; flush() sends it.
    virtual bool wants_write() const { return false; }
    virtual Io flush() { return Io::done(0); }
    // Still setting up (a TLS handshake): no application bytes yet, and it needs to read.
    virtual bool handshaking() const { return false; }

    // Nothing can be written any more, for good: a TLS 1.2 session answered the peer's
    // close_notify with its own, as that version requires, and the end of input also ends output.
    virtual bool output_ended() const { return false; }
    // Ends this side's output in order; the peer reads the end of input.
    virtual void shutdown_write() = 0;
    // After shutdown_write(): reads and drops what the peer still sends, below any TLS, until it
    // ends. Closing a socket with input unread makes the kernel answer with a reset, which throws
    // away the answers it has not yet delivered (RFC 1122 4.2.2.13).
    virtual Io discard_input() {
        std::array<std::uint8_t, 4096> sink;
        return read(sink);
    }
    // The owner expects nothing to move for a while: gives back memory the next bytes allocate
    // again (a TLS session's record buffers). False when nothing could be given back now.
    virtual bool rest() { return false; }
    // Releases the connection; nothing moves afterwards.
    virtual void close() = 0;

    virtual PeerIdentity peer() const = 0;
    // Why the last call failed, when `code` does not say it (a TLS failure); "" otherwise.
    virtual const std::string& error() const = 0;
};

}  // namespace mblab::transport
