#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// What `mblab conform-client` examines: the scenarios an examiner device plays to a Modbus/TCP
// or serial line client (master), what the client declares about itself, and the register values
// the examiner seeds and the decoys it puts in the answers a client must not take.
namespace mblab::conformance {

enum class ClientScenario : std::uint8_t {
    NoReply,           // never answered
    LateReply,         // answered after the client's timeout, decoys in the stale answer
    WrongTransaction,  // an answer under another transaction id first (decoys), then the right one
    WrongUnit,         // an answer from another unit first (decoys), then the right one
    WrongFunction,     // the answer carries another function code (decoys)
    Truncated,         // the byte count promises more than the answer holds (decoys)
    ExtraBytes,        // the answer holds bytes past its registers (decoys)
    Exception,         // an exception response, code `exception`
    SplitAnswer,       // the right answer in three segments
    TwoAnswers,        // the right answer and an unasked one (decoys) in one segment
    CloseFin,          // the first request's connection closed with a FIN, unanswered
    CloseReset,        // the same with a reset
    ByteCount,         // the byte count and the registers disagree with the quantity asked
    Pipelined,         // several requests outstanding, answered in reverse order
    BadCheck,          // a line: the first answer's CRC or LRC is wrong (decoys)
    Broadcast,         // a line: the client asks address 0, which no device answers
    Untrusted,         // mbaps: the examiner presents a certificate the client must refuse
};

struct ClientCase {
    std::string id;
    std::string title;
    std::string source;  // docs/references.md tags
    ClientScenario scenario = ClientScenario::NoReply;
    std::uint8_t exception = 0;  // ClientScenario::Exception
    // The lab PKI's server certificate the examiner presents over mbaps ("server" when empty),
    // and what is wrong with it (Untrusted).
    std::string certificate = {};
    std::string flaw = {};
};

// The Modbus/TCP scenarios, in the order they run.
const std::vector<ClientCase>& client_tcp_cases();
// Over Modbus/TCP Security: the Modbus/TCP scenarios, then the certificates a client must refuse.
const std::vector<ClientCase>& client_mbaps_cases();
// The serial line scenarios (RTU or ASCII alike), in the order they run.
const std::vector<ClientCase>& client_line_cases();

// What the client's user declares. Undeclared timeout or retries make the scenarios that need
// them N/A.
struct ClientDeclarations {
    std::uint8_t unit = 1;
    std::uint16_t address = 100;  // the first holding register the client is told to read
    std::uint16_t count = 2;      // how many
    std::optional<std::chrono::milliseconds> timeout;
    std::optional<unsigned> retries;
    bool pipelining = false;
    // Whether it can send a broadcast on a line (scenario 9 is N/A when it cannot).
    bool broadcast = false;
    // How the client signals an error: a non-zero exit status, or (set) its output matching this
    // ECMAScript regular expression.
    std::string error_pattern;
    // What a value looks like in its output; the first group, or the whole match, is read as a
    // decimal or 0x-hex number.
    std::string value_pattern = R"((?:^|[^0-9A-Za-z])(0x[0-9A-Fa-f]+|[0-9]+))";
};

// The value the examiner seeds in holding (and input) register `address`, and the decoy it puts
// for it in an answer the client must not take: far apart, so no seeded value is a decoy.
inline std::uint16_t seeded_value(std::uint32_t address) {
    return static_cast<std::uint16_t>(10000 + address % 10000);
}
inline std::uint16_t decoy_value(std::uint32_t address) {
    return static_cast<std::uint16_t>(40000 + address % 10000);
}

}  // namespace mblab::conformance
