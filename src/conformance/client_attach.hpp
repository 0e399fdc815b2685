#pragma once

#include <chrono>

#include "conformance/client_exam_wire.hpp"
#include "conformance/client_judge.hpp"

// `mblab conform-client --attach`: no command is run; a client that polls by itself (a PLC, a
// SCADA driver) meets each scenario in turn, and only the wire is judged. A scenario's window
// opens at the client's first request (or refused handshake) and closes once the client has been
// quiet for a while: a poll that comes sooner is taken for a retry.
namespace mblab::conformance {

// How long the client must be quiet for its transaction to be over: its timeout, and a little
// for it to act on it. A client's next poll comes after that, or is counted as a retry.
std::chrono::milliseconds attach_quiet(const ClientDeclarations& declared);

// Runs the wire for one scenario until the client has been quiet for attach_quiet() after it
// first asked (at most client_run_limit()), or `wait` passes without it asking (the run is then
// `stopped`).
ClientRun watch_attached(ExamWire& wire, const ClientExaminer& exam,
                         const ClientDeclarations& declared, std::chrono::milliseconds wait);

}  // namespace mblab::conformance
