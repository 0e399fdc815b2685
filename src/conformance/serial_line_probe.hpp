#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "conformance/verdict.hpp"

// What the serial suite's cases share: requests framed for the line and sent on it as bytes
// (spoiled on purpose where a case needs it), answers read as they crossed the line, and the
// words for what came back. Frames are in the line's own framing, never the catalogue's MBAP
// notation, so the evidence shows the bytes that were on the wire.
namespace mblab::conformance {

class Session;
struct Case;

// FC 03 of `count` holding registers from `address`: the serial suite's plain request.
std::array<std::uint8_t, 5> read_holding(std::uint16_t address, std::uint16_t count = 1);

// How a request is spoiled before it goes out.
enum class Spoil : std::uint8_t {
    None,
    Checksum,   // the CRC's low byte inverted (RTU), the LRC plus one (ASCII)
    LowerCase,  // ASCII: the hex digits in lower case
};

// What came back for one request on the line.
struct LineAnswer {
    Exchange exchange;  // the bytes as they crossed the line
    std::uint8_t address = 0;
    std::vector<std::uint8_t> pdu;  // empty unless a whole frame came
    // From the request's last byte written to the answer read whole, and the longest silence
    // between two reads of the answer's bytes (client::Received::largest_gap).
    std::chrono::microseconds response{0};
    std::chrono::microseconds largest_gap{0};
    bool frame() const { return exchange.status == client::ReceiveStatus::Frame; }
    bool silent() const { return exchange.received.empty(); }
};

// A silence the master leaves inside a request: `silence` after its first `after` bytes.
struct RequestPause {
    std::size_t after = 0;
    std::chrono::milliseconds silence{0};
};

class LineProbe {
  public:
    LineProbe(Session& session, const Case& c);

    std::uint8_t own() const { return own_; }
    // The address nobody on the line answers: the case's `other_address`, else the next one.
    std::uint8_t other() const { return other_; }
    std::uint16_t register_address() const { return register_; }
    std::chrono::milliseconds timeout() const;
    bool ascii() const;

    // `pdu` to `address` as the line carries it, spoiled as asked.
    std::vector<std::uint8_t> frame(std::uint8_t address, std::span<const std::uint8_t> pdu,
                                    Spoil spoil = Spoil::None) const;
    // Sends `wire` (paused as asked) and reads the first frame (or framing error) that comes
    // within `wait`.
    LineAnswer ask(std::vector<std::uint8_t> wire, std::chrono::milliseconds wait,
                   RequestPause pause = {});
    LineAnswer ask(std::uint8_t address, std::span<const std::uint8_t> pdu,
                   Spoil spoil = Spoil::None);

    // The register at the device's own address; the failure (with its evidence in `failed`) when
    // no value came.
    std::optional<std::uint16_t> read_register(std::string& failure, Exchange& failed);
    // FC 06 of `value` to the register at `address`.
    std::vector<std::uint8_t> write_request(std::uint16_t value) const;

    // "no answer from address 1: timeout after 1000 ms", "malformed answer: LRC mismatch ...",
    // "exception 02 (illegal data address)", "an answer from address 7": what came, in words.
    std::string what_came(const LineAnswer& answer) const;

  private:
    Session& session_;
    std::uint8_t own_;
    std::uint8_t other_;
    std::uint16_t register_;
};

// The outcome of a case that failed on `answer`: the reason, the exchange as evidence, and the
// session closed, so the next case starts on a clean line.
Outcome line_failure(Session& session, std::string reason, const Exchange& evidence);

}  // namespace mblab::conformance
