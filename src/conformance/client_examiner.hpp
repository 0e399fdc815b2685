#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "conformance/client_exam_scenarios.hpp"
#include "protocol/framer.hpp"

// The examiner device of `mblab conform-client` without I/O: the client's connections and bytes
// and the clock in; what to send on which connection and when, or how to end it, out. It plays
// one scenario, answers the holding and input registers with seeded_value() and every answer the
// client must not take with decoy_value(), and keeps what the wire carried for the judge. The
// owner accepts connections, feeds what they bring, and performs due() at deadline(); tests drive
// it with a manual clock.
namespace mblab::conformance {

class ClientExaminer {
  public:
    using Clock = std::chrono::steady_clock;

    struct Action {
        enum class Kind : std::uint8_t {
            Send,   // bytes, in one write (one TCP segment)
            Close,  // a FIN: the examiner's side is done
            Reset,  // an RST
        };
        Kind kind = Kind::Send;
        std::size_t connection = 0;
        std::vector<std::uint8_t> bytes = {};
        Clock::time_point at = {};
    };

    // A request as it came, for the judge.
    struct Request {
        Clock::time_point at = {};
        std::size_t connection = 0;
        std::vector<std::uint8_t> adu = {};
        std::uint16_t transaction_id = 0;
        std::uint8_t unit = 0;
        std::uint8_t function = 0;
        std::uint16_t address = 0;
        std::uint16_t count = 0;
    };

    // An answer the examiner sent, and whether it was one the client must not take.
    struct Answer {
        Clock::time_point at = {};
        std::size_t connection = 0;
        std::vector<std::uint8_t> bytes = {};
        bool decoy = false;
    };

    // `framing`: MBAP for TCP; RTU or ASCII for a line, which is connection 0 opened once.
    ClientExaminer(ClientCase scenario, ClientDeclarations declared, Clock::time_point now,
                   protocol::Framing framing = protocol::Framing::Mbap);

    // A client connected; the returned number names the connection from now on.
    std::size_t opened(Clock::time_point now);
    void received(std::size_t connection, std::span<const std::uint8_t> bytes,
                  Clock::time_point now);
    // A line went quiet: RTU ends a frame whose length its layout does not give (t3.5).
    void quiet(std::size_t connection, Clock::time_point now);
    // The client closed the connection (or it broke): nothing more is sent on it.
    void closed(std::size_t connection, Clock::time_point now);
    // The TLS handshake on the connection failed, for `reason` (the client's alert): it is over.
    void refused(std::size_t connection, std::string reason);

    // When the next action falls due; time_point::max() when none waits.
    Clock::time_point deadline() const;
    // The actions due at `now`, in order; they are the examiner's to forget.
    std::vector<Action> due(Clock::time_point now);

    const std::vector<Request>& requests() const { return requests_; }
    const std::vector<Answer>& answers() const { return answers_; }
    std::size_t connections() const { return connections_.size(); }
    std::vector<Clock::time_point> connection_times() const;
    // LateReply: the stale answer reached a connection while the client waited on it for the
    // answer to a later request.
    bool stale_met_a_wait() const { return stale_met_wait_; }
    const ClientCase& scenario() const { return scenario_; }
    // Why TLS handshakes failed, in order (Untrusted: the client's refusals).
    const std::vector<std::string>& refusals() const { return refusals_; }

    // The answer to `request` the examiner would give a well-behaved device's way, with the
    // seeded values (or decoys), under `transaction_id` and `unit`.
    std::vector<std::uint8_t> register_answer(const Request& request, std::uint16_t transaction_id,
                                              std::uint8_t unit, bool decoy) const;

  private:
    struct Connection {
        explicit Connection(protocol::Framing framing) : framer({.framing = framing}) {}
        protocol::Framer framer;
        Clock::time_point opened_at = {};
        bool open = true;
        std::vector<std::size_t> outstanding = {};  // Pipelined: requests not yet answered
    };

    void on_frame(std::size_t connection, const protocol::FrameEvent& event, Clock::time_point now);
    void on_request(const Request& request, Clock::time_point now);
    std::vector<std::uint8_t> frame(std::uint16_t transaction_id, std::uint8_t unit,
                                    std::span<const std::uint8_t> pdu) const;
    void answer(const Request& request, std::vector<std::uint8_t> bytes, bool decoy,
                Clock::time_point at);
    void answer_pipeline(std::size_t connection, Clock::time_point now);
    std::vector<std::uint8_t> right(const Request& request) const;
    std::vector<std::uint8_t> malformed(const Request& request) const;
    void schedule(Action action);

    ClientCase scenario_;
    ClientDeclarations declared_;
    Clock::time_point started_;
    protocol::Framing framing_;
    std::vector<std::unique_ptr<Connection>> connections_;
    std::vector<Request> requests_;
    std::vector<Answer> answers_;
    std::vector<std::string> refusals_;
    std::vector<Action> pending_;  // sorted by `at`, then by order of scheduling
    std::size_t asked_ = 0;        // requests to the declared unit
    Action stale_;                 // LateReply: the answer held past the timeout
    bool pending_stale_ = false;   // LateReply: stale_ is still to go
    bool stale_met_wait_ = false;  // LateReply
    Clock::time_point pipeline_at_ = Clock::time_point::max();  // Pipelined: when to answer
};

}  // namespace mblab::conformance
