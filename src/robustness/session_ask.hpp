#pragma once

#include <chrono>

#include "conformance/session.hpp"
#include "robustness/recon.hpp"

// Plain requests over a conformance session, one at a time, for the probes that learn a device
// (fuzz's reconnaissance, `mblab scan`): the session carries them over any target's framing.
namespace mblab::robustness {

// Each request goes out in a frame of its own (a new transaction id) on the session's
// connection, reopened when a request before left it closed; an answer that does not come
// within `timeout` closes it, so a late answer cannot be taken for the next one. `session` must
// outlive the returned function.
Ask session_ask(conformance::Session& session, std::chrono::milliseconds timeout);

}  // namespace mblab::robustness
