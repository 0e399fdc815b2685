#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "security/tls_channel.hpp"
#include "transport/channel.hpp"

// Modbus/TCP Security's TLS as a channel over another channel (a socket, or one end of a memory
// pair in tests). The one place that moves bytes between a security::TlsChannel and the network:
// the handshake, the cipher bytes out, and the records in. Above it the owner reads and writes
// plaintext as it would on a socket.
namespace mblab::transport {

class TlsStream final : public Channel {
  public:
    using Side = security::TlsChannel::Side;

    // Over a channel it owns (a socket it closes).
    TlsStream(std::unique_ptr<Channel> lower, const security::SharedContext& context, Side side,
              std::string_view server_name = {});
    // Over a channel that outlives it.
    TlsStream(Channel& lower, const security::SharedContext& context, Side side,
              std::string_view server_name = {});
    TlsStream(const TlsStream&) = delete;
    TlsStream& operator=(const TlsStream&) = delete;

    security::TlsChannel& session() { return tls_; }
    const security::TlsChannel& session() const { return tls_; }
    Channel& lower() { return *lower_; }

    // A client's first flight, sent as far as the lower channel takes it.
    Io start();
    // Moves the handshake on: sends what TLS has and reads what the peer sent until it is over
    // or must wait. Done once open. WouldBlock: wait for input, and for room while
    // wants_write(). EndOfInput: the peer closed first. Failed: `code` or error() says why, and
    // the alert that tells the peer went out as far as it could.
    Io handshake();
    // Queues close_notify and sends it as far as the lower channel takes it.
    Io close_notify();
    // The peer sent bytes, or closed, since this stream began: a refusal was heard, not guessed.
    bool heard_peer() const { return heard_; }

    // Moves a handshake on first; EndOfInput once the peer's close_notify (or a FIN) came.
    Io read(std::span<std::uint8_t> out) override;
    // Encrypts the buffers as one record (up to kPlainBatch bytes of several buffers) once the
    // records before it are out; WouldBlock while they are not.
    Io writev(std::span<const iovec> buffers) override;
    bool has_input() const override { return tls_.has_input(); }
    bool output_ended() const override {
        return tls_.state() == security::TlsChannel::State::Closed;
    }
    // The last read of the lower channel filled a record's worth.
    bool input_may_remain() const override { return lower_->input_may_remain(); }
    bool wants_write() const override { return !tls_.output().empty(); }
    Io flush() override;
    bool handshaking() const override;
    // close_notify, then the lower channel's end of output: at once, or from the flush() that
    // sends the rest of a close_notify the lower channel had no room for (wants_write() till then).
    void shutdown_write() override;
    Io discard_input() override { return lower_->discard_input(); }
    bool rest() override { return tls_.release_buffers(); }
    void close() override { lower_->close(); }
    PeerIdentity peer() const override;
    const std::string& error() const override { return error_; }

    // A TLS record's worth: one read takes a whole record when the peer sent one.
    static constexpr std::size_t kCipherChunk = 16 * 1024 + 512;
    static constexpr std::size_t kPlainBatch = 16 * 1024;

  private:
    // One read of the lower channel, handed to TLS.
    Io pull();
    // What a session no longer open reads: the end of input, or its failure.
    Io ended();

    std::unique_ptr<Channel> owned_;
    Channel* lower_;
    security::TlsChannel tls_;
    std::string error_;
    bool heard_ = false;
    bool end_owed_ = false;  // shutdown_write() waits for the lower channel to take the rest
};

}  // namespace mblab::transport
