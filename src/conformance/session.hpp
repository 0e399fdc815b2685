#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "client/link.hpp"
#include "client/target.hpp"
#include "conformance/dut.hpp"
#include "conformance/line_evidence.hpp"

namespace mblab::conformance {

struct EngineOptions {
    std::chrono::milliseconds timeout{1000};  // for each answer
    std::chrono::milliseconds connect_timeout{3000};
    // Requests in flight during sweeps and scans. 1 runs them as the policy writes them
    // (transaction id 0, one outstanding); more is a speed option that numbers the requests and
    // pairs answers by transaction id.
    std::size_t pipeline_depth = 1;
    // How long the device is watched after each case for bytes nobody asked for (a duplicate
    // answer, noise between cases), before the case's verdict is given.
    std::chrono::milliseconds settle{10};
};

// Told how far a long procedure has come; the console shows it on a TTY.
class Progress {
  public:
    virtual ~Progress() = default;
    virtual void update(std::string_view what, std::size_t done, std::size_t total) = 0;
    virtual void clear() = 0;
};

// The connection to the device under test, shared by every case of a run. It reconnects when a
// case left it closed or out of step, and counts the requests sent.
//
// Cases are written in the catalogue's notation, Modbus/TCP frames. The session has one link,
// whatever the target: over RTU, ASCII or RTU over TCP it writes each request's unit id and PDU
// in that framing, one request at a time, and the link's framer reads the answer's header and
// PDU. The answer is handed back in the catalogue's notation (the request's transaction id, unit
// id = the address that answered), laid out from those fields, so every case is judged the same
// way; cases that test MBAP itself are N/A there (`requires mbap`). The frames as the line
// carried them are kept for the case, so that its evidence shows them (show_as_on_line).
class Session {
  public:
    Session(client::Target target, Dut dut, EngineOptions options,
            client::LinkObserver* observer = nullptr, Progress* progress = nullptr);
    Session(const client::Endpoint& endpoint, Dut dut, EngineOptions options,
            client::LinkObserver* observer = nullptr, Progress* progress = nullptr);

    // The IP host of the device: nullopt on a serial line.
    std::optional<std::string> host() const;
    // Where the security suite reaches the device over Modbus/TCP Security: the target when it is
    // mbaps://, or the port set here (the built-in device serves both); nullopt when nowhere.
    const std::optional<client::Target>& secure_target() const { return secure_target_; }
    void set_secure_target(client::Target target) { secure_target_ = std::move(target); }
    // Links come from `dial` instead of the target's address (the target still says the
    // framing): a test's device in memory.
    void dial_with(client::Dial dial) { dial_ = std::move(dial); }
    client::Framing framing() const;
    const client::Target& target() const { return target_; }
    const Dut& dut() const { return dut_; }
    const DutFacts& facts() const { return facts_; }
    const EngineOptions& options() const { return options_; }
    Progress* progress() const { return progress_; }

    // Opens the connection or port when it is not open; false with `error` set when the device
    // cannot be reached.
    bool connect(client::LinkError& error);
    // connect() for a device that has just closed a connection or been sent something hard: a
    // refusal is tried again a few times over about a second and a half before it counts, since
    // a conformant device with one connection slot may still be freeing it.
    bool reconnect(client::LinkError& error);
    // Whether a connection was ever made in this session: a device that accepted one and refuses
    // the next has stopped serving.
    bool ever_connected() const { return ever_connected_; }
    // Closes the connection so the next case starts on a fresh one.
    void close();

    // Sends `count` requests held in `bytes`, written as pieces cut at `split` with `delay`
    // between them (so they leave as separate TCP segments). Over a serial framing `bytes` must
    // be whole MBAP frames that carry a plain request each, and `split` must be empty.
    bool send(std::span<const std::uint8_t> bytes, std::size_t count, client::LinkError& error,
              std::span<const std::size_t> split = {},
              std::chrono::milliseconds delay = std::chrono::milliseconds(0));
    client::Received receive_frame(std::chrono::milliseconds timeout);
    client::Received receive_any(std::chrono::milliseconds timeout);

    // The serial suite's seam on a line: `wire` goes out exactly as given (a wrong CRC, lower-case
    // hex), past the framing send() applies; refused over Modbus/TCP.
    bool send_on_wire(std::span<const std::uint8_t> wire, client::LinkError& error);
    // The next frame or framing error as it crossed the line (wire bytes; the header as the
    // link's framer read it), not in the catalogue's notation.
    client::Received receive_from_wire(std::chrono::milliseconds timeout);

    // A case begins: the traffic from here on is the case's (a capture notes its id beside each
    // packet), and its frames on a line are kept for its evidence.
    void start_case(std::string_view id);
    // The case is over; what follows belongs to no case, and its frames are let go. Outside a
    // case (a load run) no frame is kept.
    void end_case();
    // This case's frames on a line, as the line carried them, by their catalogue notation.
    const LineFrames& line_frames() const { return line_frames_; }
    // The role the tester's certificate carries over mbaps://, once a session was
    // made; empty on any other link and for a certificate without a role.
    const std::string& certificate_role() const { return certificate_role_; }

    std::size_t requests() const { return requests_; }
    // Whether the device ever sent a byte on any connection of this session.
    bool heard() const { return heard_; }
    // Whether no_answer_hint has asked the other unit ids.
    bool probed() const { return probed_; }
    // Requests the current connection has carried (a device that stops after N shows here).
    std::size_t connection_requests() const { return connection_requests_; }
    // The last whole frame received on this connection, to recognise an answer sent twice.
    const std::vector<std::uint8_t>& last_frame() const { return last_frame_; }

    // Whatever the device sent that nobody asked for, waiting up to `wait` for it: bytes are
    // returned (the first few kilobytes, the rest counted in `discarded`); an empty result
    // when it stayed quiet or the connection is not open.
    client::Received take_unasked(std::chrono::milliseconds wait);

    // "; the device answers unit 255: try --unit 255" after a request that went unanswered
    // (client::probe_units, asked once per run); empty when nothing more can be said.
    std::string no_answer_hint(std::span<const std::uint8_t> request);

  private:
    bool send_on_line(std::span<const std::uint8_t> bytes, client::LinkError& error);
    // An answer from a line in the catalogue's notation; its line bytes are noted in
    // line_frames_ for the evidence.
    client::Received in_case_notation(client::Received received);

    client::Target target_;
    std::optional<client::Target> secure_target_;
    client::Dial dial_;
    Dut dut_;
    DutFacts facts_;
    EngineOptions options_;
    client::LinkObserver* observer_;
    Progress* progress_;
    std::unique_ptr<client::Link> link_;
    std::uint16_t line_transaction_ = 0;  // of the request last sent on a line
    LineFrames line_frames_;
    bool in_case_ = false;
    std::size_t requests_ = 0;
    std::size_t connection_requests_ = 0;
    std::vector<std::uint8_t> last_frame_;
    std::string certificate_role_;
    bool probed_ = false;
    bool heard_ = false;
    bool ever_connected_ = false;
};

// Why a case cannot run over the session's framing (pipelined or split requests are TCP stream
// tests; a request whose MBAP header is not plain tests MBAP), or nothing.
std::optional<std::string> mbap_only_reason(const Session& session, bool pipelined, bool split,
                                            std::span<const std::uint8_t> request);

}  // namespace mblab::conformance
