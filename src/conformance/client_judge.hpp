#pragma once

#include <chrono>
#include <string>

#include "conformance/client_applicable.hpp"
#include "conformance/client_examiner.hpp"
#include "conformance/verdict.hpp"

// The verdict of one scenario of `mblab conform-client`: what the wire carried (the examiner's
// record) and what the client's command did, against what the client declared.
namespace mblab::conformance {

// How the client's command ended.
struct ClientRun {
    int exit_status = 0;   // as the shell gives it: 128 + N for signal N
    bool stopped = false;  // still running at the scenario's limit: the examiner killed it
    std::string output;    // standard output and standard error, in the order they came
    std::chrono::milliseconds elapsed{0};
    std::chrono::milliseconds limit{0};                // how long it was given
    std::chrono::steady_clock::time_point ended = {};  // when it was seen to end
    // --attach: no command ran; only the wire is judged (no exit status, no output).
    bool attached = false;
};

Outcome judge_client(const ClientExaminer& exam, const ClientDeclarations& declared,
                     const ClientRun& run);

// The longest a scenario lets the client run: every try's timeout twice over, and some.
std::chrono::milliseconds client_run_limit(const ClientDeclarations& declared);

}  // namespace mblab::conformance
