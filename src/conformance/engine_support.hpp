#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/link.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/pattern.hpp"
#include "conformance/session.hpp"
#include "conformance/verdict.hpp"

// The engine's reading of answers: what it takes from the catalogue's MBAP notation, how
// pipelined answers are paired with their steps, how a device-id stream is followed, and what
// exception 01 says is not served. Only engine*.cpp include this.
namespace mblab::conformance::engine_detail {

inline Outcome verdict(Verdict v, std::string reason) {
    return Outcome{v, std::move(reason), {}, {}};
}

// N/A: the case needs DUT key `key`, which was not declared.
inline Outcome not_declared(const std::string& key) {
    return Outcome{Verdict::NotApplicable, "the DUT does not declare " + key, {}, key};
}

// N/A for a requirement the DUT does not meet.
inline Outcome not_met(const Unmet& why) {
    return Outcome{Verdict::NotApplicable, why.reason, {}, why.undeclared};
}

inline constexpr std::uint8_t kEncapsulated = 0x2B;
inline constexpr std::uint8_t kMeiReadDeviceId = 0x0E;
// In a 2B / 0E request PDU: function, MEI type, read device id code, object id.
inline constexpr std::size_t kReadCodeAt = 2;

struct ResolvedStep {
    const Step* step = nullptr;
    std::vector<std::uint8_t> request;
    std::vector<ResolvedPattern> expect;
};

bool is_exception(const Exchange& exchange, protocol::ExceptionCode code);

// The PDU of a request or answer in the catalogue's notation (an MBAP frame); empty when there is
// none.
std::span<const std::uint8_t> pdu_of(std::span<const std::uint8_t> adu);

// Checks every field the spec fixes in an answer the pattern accepted; the step's failure when
// one is wrong.
std::optional<std::string> spec_failure(const Exchange& exchange);

// A stream read of device identification (2B / 0E, codes 01..03) whose answer says more
// follows: the same request is asked again from the next object id until none follows. Each
// answer is judged like the first; a stream that asks for an object twice never ends. A basic
// stream from object 00 must have delivered the mandatory objects when it ends.
std::optional<Outcome> follow_device_id_stream(Session& session, const Exchange& first,
                                               std::chrono::milliseconds timeout);

// Pipelined answers may come in any order ([TCPG]: the transaction id pairs them); each goes to
// the unanswered step with its transaction id, or else to the first unanswered step.
void collect_answers(Session& session, const std::vector<ResolvedStep>& steps,
                     std::vector<std::optional<client::Received>>& answers);

// What exception 01 says is not served, for a request PDU: the function code, and for FC 08 its
// sub-function, for FC 2B its MEI type, which [APP] also refuses with 01 when they are not
// served (an unknown diagnostic sub-function is 01 from a device that serves FC 08).
std::optional<std::uint32_t> service_key(std::span<const std::uint8_t> pdu);

// "function 03", "function 08 sub-function 0002", "function 2B MEI type 0E".
std::string service_name(std::span<const std::uint8_t> pdu);

// Over mbaps:// a role's rights refuse a request with exception 01 as a device without the
// function does ([SEC] R-31): ", or the certificate's role ReadOnly may not write ([SEC] R-31)"
// ("may not use function 0B" for a function that writes nothing) to add to an exception 01's
// reason; empty when the tester's certificate carries no role.
std::string role_hint(const Session& session, std::span<const std::uint8_t> pdu);

}  // namespace mblab::conformance::engine_detail
