#pragma once

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/link_types.hpp"
#include "conformance/pattern.hpp"
#include "conformance/verdict.hpp"
#include "protocol/exception_code.hpp"

namespace mblab::conformance {

struct Judgement {
    int matched = -1;  // index of the alternative that matched, -1 for none
    Exchange exchange;
};

// Compares what came back with each expected pattern; the exchange keeps the comparison with the
// matching one, or with the closest when none matches.
Judgement judge(std::span<const std::uint8_t> sent, client::Received received,
                std::chrono::milliseconds waited, const std::vector<ResolvedPattern>& alternatives);

// The transaction id of an MBAP request or answer (0 when too short to hold one).
std::uint16_t transaction_of(std::span<const std::uint8_t> adu);

// The exception code of an answer that is the request's function code with the exception bit
// and one code; nullopt for any other answer.
std::optional<protocol::ExceptionCode> exception_answer(std::span<const std::uint8_t> request,
                                                        std::span<const std::uint8_t> answer);

// The device answered the request's function code with exception `code`.
bool is_exception_answer(std::span<const std::uint8_t> request, std::span<const std::uint8_t> frame,
                         protocol::ExceptionCode code);

// Bytes that came when nothing was asked, in words a vendor reads: "duplicate answer: ..." when
// they are `last_frame` again, else "unsolicited bytes: ..." with their count and first bytes.
// `when` places them: "after this answer,".
std::string describe_unasked(const client::Received& got, std::string_view when,
                             std::span<const std::uint8_t> last_frame);

// The evidence for bytes that came unasked after `last_request`: what came, nothing expected.
Exchange unasked_exchange(client::Received got, std::span<const std::uint8_t> last_request);

// A frame that came instead of an answer and repeats the answer before it.
std::string describe_duplicate(std::span<const std::uint8_t> frame);

// One line saying what went wrong: "timeout after 1000 ms", "exception 02 (illegal data
// address)", "wrong transaction id, length field", ... `carried` is the framing the exchange
// crossed: on a line the MBAP header of the catalogue's notation was laid out by the tester, so
// its fields are never named.
std::string describe_failure(const Exchange& exchange,
                             client::Framing carried = client::Framing::Mbap);

}  // namespace mblab::conformance
