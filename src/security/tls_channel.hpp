#pragma once

#include <openssl/ssl.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "security/certificate_role.hpp"
#include "security/queue_bio.hpp"
#include "security/tls_context.hpp"

// One TLS session without I/O: bytes from the network and plaintext in, bytes for the network and
// plaintext out, over two byte queues (security/queue_bio). The owner moves cipher bytes between
// the socket and received()/output(); the MBAP session above reads and writes plaintext and never
// knows TLS is there. Tests drive a client and a server channel into each other with no socket at
// all.
namespace mblab::security {

// The last TLS alert the peer sent: how a server says why it ended a handshake or refused a
// renegotiation.
struct TlsAlert {
    bool received = false;
    bool fatal = false;
    int description = 0;  // RFC 8446 6: 100 no_renegotiation, 70 protocol_version, ...
    std::string text;     // "fatal protocol version"

    static constexpr int kCloseNotify = 0;
    static constexpr int kNoRenegotiation = 100;
};

struct TlsPeer {
    std::string version;   // "TLSv1.3"
    std::string cipher;    // "TLS_AES_256_GCM_SHA384"
    std::string subject;   // of the peer's certificate, "" when it sent none
    RoleReading role;      // read once, at the handshake (kept by a resumed session)
    RoleReading own_role;  // of the certificate this side presented
    bool resumed = false;
};

class TlsChannel {
  public:
    enum class Side : std::uint8_t { Server, Client };
    enum class State : std::uint8_t {
        Handshaking,
        Open,
        Closed,  // the peer sent close_notify, or we did and the peer answered it
        Failed,  // the handshake or a record failed: error() says why; output() may hold an alert
    };

    // `server_name` is the host a client connects to: its certificate must name it (SAN), when
    // the context verifies the server. A server channel ignores it.
    TlsChannel(const SharedContext& context, Side side, std::string_view server_name = {});
    ~TlsChannel();
    TlsChannel(const TlsChannel&) = delete;
    TlsChannel& operator=(const TlsChannel&) = delete;

    // A client's first flight (ClientHello) into output(); a server waits for it.
    void start();
    // Bytes that came from the network.
    void received(std::span<const std::uint8_t> bytes);
    // Moves the handshake on and decrypts what has come: up to out.size() plaintext bytes, 0 when
    // none is ready (state() says whether more can come).
    std::size_t read(std::span<std::uint8_t> out);
    // Whether plaintext or records are waiting that read() has not taken.
    bool has_input() const;
    // A TLS 1.3 server read the peer's close_notify and may still write until close(); the
    // state stays Open meanwhile. (TLS 1.2, and a client, answer close_notify at once: Closed.)
    bool input_ended() const { return input_ended_; }
    // Application data may still come: open, and no close_notify read.
    bool input_open() const { return state_ == State::Open && !input_ended_; }
    // Encrypts every byte (an open channel only); false when the channel cannot take them.
    bool write(std::span<const std::uint8_t> plain);
    // Queues close_notify; the channel ends when the peer answers (or the owner stops waiting).
    void close();

    // Bytes for the network, in order; sent() drops what the socket took. Valid until the next
    // call into the channel.
    std::span<const std::uint8_t> output() const { return output_.bytes(); }
    void sent(std::size_t count) { output_.drop(count); }
    // Gives back the record buffers (about 33 KB) and the queues' storage of an open session
    // with nothing in them: a session at rest holds no record, and the next one allocates them
    // again. False (and nothing changed) while any record, byte or plaintext is in them.
    bool release_buffers();
    // A release_buffers() gave the buffers back and no byte has moved since.
    bool resting() const { return resting_; }

    State state() const { return state_; }
    const std::string& error() const { return error_; }
    // Valid once the handshake is over.
    const TlsPeer& peer() const { return peer_; }

    // For clients that resume: the session to offer, and the one to keep for the next time.
    void offer_session(SSL_SESSION* session);
    SSL_SESSION* take_session() const;  // the caller frees it (SSL_SESSION_free)
    // The security suite's renegotiation attempt; state() and error() say how it went.
    bool request_renegotiation();
    // Whether the peer's hello carried the RFC 5746 renegotiation indication (TLS 1.2; a TLS 1.3
    // session has no renegotiation, and says true).
    bool secure_renegotiation() const;
    const TlsAlert& alert_received() const { return alert_; }

  private:
    void handshake();
    void fail(const char* fallback);
    void finish_handshake();
    // Why the peer's certificate was refused, from the verification result.
    std::string verify_failure() const;

    // The BIOs SSL_free() frees use them: members live until the destructor's body has run.
    ByteQueue input_;   // network -> OpenSSL
    ByteQueue output_;  // OpenSSL -> network
    SSL* ssl_ = nullptr;
    Side side_;
    State state_ = State::Handshaking;
    std::string error_;
    std::string role_refusal_;  // why the verification refused the client's role
    TlsPeer peer_;
    TlsAlert alert_;
    bool input_ended_ = false;
    bool resting_ = false;

    friend void note_alert(const SSL* ssl, int where, int value);
};

std::string_view state_name(TlsChannel::State state);

}  // namespace mblab::security
