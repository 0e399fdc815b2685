#pragma once

#include <optional>

#include "conformance/client_exam_scenarios.hpp"
#include "conformance/verdict.hpp"

// Which scenarios of `mblab conform-client` apply to a client: the rest are N/A with the reason.
namespace mblab::conformance {

// The declarations a scenario needs and does not have: N/A, with the reason and the flag.
std::optional<Outcome> undeclared(const ClientCase& scenario, const ClientDeclarations& declared);
// Under --attach, a scenario judged only by what the client does with an answer, which shows in
// its output alone: N/A, with the reason.
std::optional<Outcome> needs_output(const ClientCase& scenario);

}  // namespace mblab::conformance
