#pragma once

#include <string>

#include "conformance/provenance.hpp"
#include "robustness/fuzz_run.hpp"
#include "robustness/monitor_junit.hpp"

// What a robustness run found, for people and for CI.
namespace mblab::robustness {

// The reconnaissance, as lines printed before the run.
std::string recon_text(const Recon& recon);
// The verdict, the counts, the finding and its reproducer.
std::string summary_text(const FuzzResult& result);
std::string json_report(const FuzzResult& result, const conformance::Provenance& provenance);
// One <testcase> per bad-input class; the finding's class fails with the reproducer's hex, a
// class with no case run is skipped. With the monitor's `suite` (monitor_junit_suite()), its
// phases and verdict as a second test suite. Valid against tests/junit-10.xsd.
std::string junit_report(const FuzzResult& result, const conformance::Provenance& provenance,
                         const JunitSuite* suite = nullptr);

}  // namespace mblab::robustness
