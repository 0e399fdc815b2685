#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "client/client_error.hpp"
#include "client/frame_observer.hpp"
#include "client/link.hpp"
#include "protocol/result.hpp"

// Request / answer exchanges over a Link: transaction ids, timeouts, retries and reconnection.
// Blocking: one request is outstanding at a time.
namespace mblab::client {

struct TransactionOptions {
    std::uint8_t unit = 1;
    std::chrono::milliseconds timeout{1000};  // for connecting and for each answer
    unsigned retries = 0;                     // extra tries after a timeout or a lost connection
    // After a final timeout, ask once which other unit id answers (off for `watch`, whose polls
    // must not be interleaved with other requests).
    bool probe_units = true;
};

using LinkOpener = std::function<protocol::Result<std::unique_ptr<Link>, LinkError>()>;
using Done = std::monostate;

class Transactor {
  public:
    // `target` names the device in messages; `opener` is called for the first connection and
    // again whenever the device closed the last one.
    Transactor(std::string target, LinkOpener opener, TransactionOptions options,
               FrameObserver* observer = nullptr);

    // Connects now, so that an unreachable target fails before anything else happens.
    protocol::Result<Done, ClientError> connect();
    // The TLS session of the link now open (mbaps://), else nullptr.
    const security::TlsPeer* tls_peer() const { return link_ ? link_->tls_peer() : nullptr; }

    // Sends a request PDU and returns the answer's PDU. The answer has passed the frame checks:
    // its transaction id, unit and function code (the request's, or it with 0x80) match. Late
    // answers to requests that timed out earlier on the same connection are skipped.
    protocol::Result<std::vector<std::uint8_t>, ClientError> transact(
        std::span<const std::uint8_t> request);

    // Sends a request that the device does not answer (FC 08 sub-function 04).
    protocol::Result<Done, ClientError> send_only(std::span<const std::uint8_t> request);

    const std::string& target() const { return target_; }
    const TransactionOptions& options() const { return options_; }

  private:
    struct Failure {
        ClientError error;
        bool retry = false;  // a timeout or a lost connection: another try may work
    };
    using Attempt = protocol::Result<std::vector<std::uint8_t>, Failure>;

    protocol::Result<Done, ClientError> ensure_link();
    protocol::Result<std::uint16_t, Failure> send(std::span<const std::uint8_t> request);
    Attempt attempt(std::span<const std::uint8_t> request);
    Attempt await_answer(std::uint16_t transaction_id, std::uint8_t function);
    // The answer if `frame` is one for this request, nothing if it is a late answer to skip.
    std::optional<Attempt> judge(std::span<const std::uint8_t> frame, std::uint16_t transaction_id,
                                 std::uint8_t function);
    Failure bad_answer(std::string message);
    Failure lost(std::string message);
    void drop_link();
    void note(const std::string& text);
    // After the final timeout of a request: which other unit id (1, 255, 0 over TCP; 1 on a
    // line) answers, asked once per transactor; "; the device answers unit 255: try --unit 255".
    std::string unit_hint();

    std::string target_;
    LinkOpener opener_;
    TransactionOptions options_;
    FrameObserver* observer_;
    std::unique_ptr<Link> link_;
    std::uint16_t next_transaction_id_ = 1;
    // Transaction ids sent on this connection whose answers never came.
    std::vector<std::uint16_t> unanswered_;
    // An answer the wait for the current request discarded (another transaction's, another
    // unit's), for the timeout's message.
    std::string discarded_;
    bool probed_ = false;  // unit_hint() asked the other units already
};

}  // namespace mblab::client
