#pragma once

#include <cstdint>
#include <string>

#include "client/target.hpp"
#include "conformance/capture.hpp"
#include "conformance/provenance.hpp"
#include "robustness/fuzz_run.hpp"

// What `mblab fuzz` leaves behind once a run is over: the summary on the console, each finding's
// reproducer (hex lines and a pcapng of its frames), the JSON and JUnit reports and the run's
// capture, where the command line asked for them.
namespace mblab::cli {

struct FuzzOutputs {
    std::string reproducer;  // the finding's hex lines; FILE.pcapng beside it
    std::string json;
    std::string junit;
    std::string pcap;
};

// Prints the summary and writes the files; the command's exit status (2 when a file cannot be
// written, 1 for a finding, 0 otherwise).
int write_fuzz_outputs(const robustness::FuzzResult& result, const client::Target& target,
                       const FuzzOutputs& outputs, const conformance::Capture& capture,
                       const conformance::Provenance& provenance);

}  // namespace mblab::cli
