#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "device/request_handler.hpp"
#include "device/role_rules.hpp"
#include "server/mbap_driver.hpp"
#include "server/mbap_session.hpp"
#include "server/server_stats.hpp"
#include "support/manual_clock.hpp"
#include "transport/memory_channel.hpp"
#include "transport/tls_stream.hpp"

// An MbapSession driven the way TcpSession drives it, over an in-memory stream and a manual
// clock, so that a test reads as a protocol trace: the client sends hex, time passes, the device
// answers hex.
namespace mblab::test {

// The device behind the session, a small gateway double:
//   unit 1, FC 03: holding register N holds N; FC 06: echoed;
//           FC 41 NN: echoed after NN * 10 ms (fault "delay"); FC 42: no answer (fault "drop");
//           FC 43: the connection is closed (fault "close")
//   unit 0: a broadcast: executed, never answered
//   unit 9: behind a serial line: answered like unit 1 when the test says the line answered
//           (RequestHandler::handle_or_defer); a broadcast goes there too once
//           `broadcasts_on_line` is set
class TraceDevice final : public device::RequestHandler {
  public:
    static constexpr std::uint8_t kLineUnit = 9;

    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override;
    std::optional<device::Reply> handle_or_defer(const device::RequestContext& context,
                                                 std::span<const std::uint8_t> request,
                                                 std::span<std::uint8_t> response,
                                                 device::Deferral& deferral) override;
    // The serial line answers the oldest request waiting on it.
    void line_answers();
    std::size_t waiting_on_line() const { return line_.size(); }

    bool broadcasts_on_line = false;
    int broadcasts = 0;

  private:
    struct LineRequest {
        device::RequestContext context;
        std::vector<std::uint8_t> pdu;
        device::DeferredDone done;
    };
    std::deque<LineRequest> line_;
};

// Modbus/TCP Security in a trace: the server's TLS context and the roles it grants, and the
// client's context. The trace's client then speaks TLS over the memory pair.
struct TraceTls {
    security::SharedContext server;
    security::SharedContext client;
    std::shared_ptr<const device::RoleRules> roles;
    bool handshake = true;  // the client's handshake done by the constructor
};

// The real server driver (MbapDriver, as TcpSession runs it) over a memory pair and a manual
// clock, so that a test reads as a protocol trace: the client sends hex, time passes, the device
// answers hex.
class SessionTrace final : private server::MbapSession::Host {
  public:
    explicit SessionTrace(server::MbapSessionLimits limits = {});
    explicit SessionTrace(const TraceTls& tls, server::MbapSessionLimits limits = {});

    // The client writes these bytes; the session reads and answers what it can.
    void client_sends(std::string_view hex);
    void client_sends_byte_by_byte(std::string_view hex, std::chrono::milliseconds gap);
    void client_shuts_down();
    void client_resets();
    // Over TLS: moves the client's handshake on until it is over or nothing moves; true when the
    // session is open.
    bool client_handshakes();
    // What a readiness loop does: tells the driver what its end of the pair is ready for, until
    // it is ready for nothing the driver wants.
    void run();
    // Time passes; the driver is woken at each of its deadlines on the way.
    void after(std::chrono::milliseconds time);
    // Everything the device sent that the client has not read yet, as "00 01 ...".
    std::string client_reads();
    // Takes what arrived, lets the session send more, and again until nothing comes.
    std::string client_reads_everything();
    // What the client reads now is exactly `hex` (spaces anywhere); nothing when empty.
    void device_answers(std::string_view hex);
    void device_says_nothing() { device_answers(""); }

    // Whether the session reads its socket.
    bool reading() const { return !closed() && session_.wants_input(); }
    // The session is over: the driver closed the connection at once, or it ended its output
    // after its answers (and may still read what the client sends, until the client ends).
    bool closed() const { return driver_.closed() || driver_.lingering(); }
    // The driver let the connection go: its owner closes the descriptor now.
    bool released() const { return driver_.closed(); }
    bool lingering() const { return driver_.lingering(); }
    bool client_sees_end_of_input() const { return stream_.client().at_end_of_input(); }

    TraceDevice& device() { return device_; }
    // The client's end of the pair (below TLS, when there is TLS).
    transport::MemoryPair::End& client() { return stream_.client(); }
    // The session's end, for failures on its side (short writes).
    transport::MemoryPair::End& server_end() { return stream_.server(); }
    // What the client reads and writes through: its TLS session, or its end of the pair.
    transport::Channel& client_channel();
    transport::TlsStream* client_tls() { return client_tls_.get(); }
    transport::TlsStream* server_tls() { return server_tls_.get(); }
    server::MbapSession& session() { return session_; }
    server::MbapDriver& driver() { return driver_; }
    const server::ServerStats& stats() const { return stats_; }
    ManualClock& clock() { return clock_; }
    int busy_replies() const { return busy_replies_; }
    // The answers the session gave itself, as "unit 1 from PEER: 03 00 08 00 01 -> 06".
    const std::vector<std::string>& own_answers() const { return own_answers_; }
    // Why the server refused a TLS client, in order.
    const std::vector<std::string>& refusals() const { return refusals_; }

  private:
    device::DeferredDone route_deferred(std::uint32_t ticket,
                                        const protocol::MbapHeader& request) override;
    void on_own_answer(const device::RequestContext& context, std::span<const std::uint8_t> request,
                       protocol::ExceptionCode code) override;

    TraceDevice device_;
    server::ServerStats stats_;
    ManualClock clock_;
    transport::MemoryPair stream_;
    std::vector<std::string> refusals_;
    server::ServerOptions options_;
    std::unique_ptr<transport::TlsStream> server_tls_;
    std::unique_ptr<transport::TlsStream> client_tls_;
    server::MbapSession session_;
    server::MbapDriver driver_;
    int busy_replies_ = 0;
    std::vector<std::string> own_answers_;
};

}  // namespace mblab::test
