#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include "security/tls_channel.hpp"
#include "server/mbap_session.hpp"
#include "server/server_options.hpp"
#include "server/server_stats.hpp"
#include "transport/channel.hpp"
#include "transport/linger.hpp"

namespace mblab::server {

// Moves bytes and time between one transport::Channel and an MbapSession: the loop of a Modbus/TCP
// connection, with no descriptor, poller or timer of its own. TcpSession runs it on a socket (or
// TLS over one) from the server's epoll loop; tests run the same loop over a memory pair on a
// manual clock. After each call the owner asks wants_read(), wants_write() and deadline() what to
// wait for, and closes the channel once closed() says so.
//
// Over TLS (options.tls set, the channel a transport::TlsStream) it also bounds the handshake by
// options.handshake_limit, authorizes the session by the role in the client's certificate, and
// refuses a client whose first plaintext is a bare PDU. A TLS session gives its record buffers
// back (Channel::rest()) after its handshake and whenever nothing has moved for kRestAfter.
class MbapDriver {
  public:
    // A client that polls more often than this keeps its buffers; one that polls more seldom
    // pays an allocation and a free per record, as every session did with the release mode.
    static constexpr std::chrono::seconds kRestAfter{1};

    MbapDriver(transport::Channel& channel, MbapSession& session, const ServerOptions& options,
               ServerStats& stats, Clock::time_point now);

    // The channel has input (or an error, or an end) to read.
    void readable(Clock::time_point now);
    // The channel has room again.
    void writable(Clock::time_point now);
    // The clock reached deadline().
    void on_time(Clock::time_point now);
    // A deferred request's answer came (on this thread).
    void answer_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                         const device::Reply& reply, std::span<const std::uint8_t> pdu,
                         Clock::time_point now);
    // The owner ends the connection (the table gave its place to a newcomer, the server stops).
    void stop() { closed_ = true; }

    bool wants_read() const;
    bool wants_write() const { return write_blocked_; }
    // The last read may have left input in the channel: it filled all the room it was given, or
    // it went through TLS, whose records need not end where a read does.
    bool input_may_remain() const { return input_may_remain_; }
    Clock::time_point deadline() const;
    bool handshaking() const { return channel_.handshaking(); }
    bool closed() const { return closed_; }
    // The session ended its output after its answers and reads what the client still sends
    // (transport::Linger), so that the close leaves no input unread to make the kernel reset the
    // connection under the last answers.
    bool lingering() const { return !closed_ && linger_.active(); }

  private:
    // One read of the channel into the session; false when nothing was handed over.
    bool take(Clock::time_point now);
    // Sends what the session has ready until the channel is full or nothing is ready, then
    // ends the connection if the session is done.
    void flush(Clock::time_point now);
    // Records decrypted but not yet handed over wait for the session to take input again; no
    // socket event would bring them.
    void drain(Clock::time_point now);
    void end_input(Clock::time_point now);
    void on_handshake(const security::TlsPeer& peer);
    void refuse_handshake(const std::string& reason);
    // Ends this side's output (over TLS close_notify first), then closes when the client has
    // ended too, else lingers.
    void linger(Clock::time_point now);
    // While lingering: sends what is left of this side's end (a close_notify that found the
    // socket full); closes once it is out and the client has ended too.
    void send_end();
    // Reads and drops a bounded amount of what the lingering client sent; closes at its end.
    void discard(Clock::time_point now);
    // Counts and reports a client refused after its handshake, then ends its session.
    void refuse_client(const std::string& reason, Clock::time_point now);
    // Bytes came or went over TLS: the session rests kRestAfter from now unless more move.
    void moved(Clock::time_point now) {
        if (tls_ && handshake_deadline_ == Clock::time_point::max()) rest_at_ = now + kRestAfter;
    }
    // Rests the channel once rest_at_ is reached; refused (a record on its way), tries again later.
    void rest_if_due(Clock::time_point now);

    transport::Channel& channel_;
    MbapSession& session_;
    const ServerOptions& options_;
    ServerStats& stats_;
    const bool tls_;
    Clock::time_point handshake_deadline_ = Clock::time_point::max();
    Clock::time_point rest_at_ = Clock::time_point::max();  // over TLS, once open
    transport::Linger linger_;
    bool closed_ = false;
    bool write_blocked_ = false;  // the channel took less than it was given
    bool input_may_remain_ = false;
    bool input_ended_ = false;     // the client sends nothing more
    bool seen_plaintext_ = false;  // the first plaintext was checked for a bare PDU
};

}  // namespace mblab::server
