#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "robustness/monitor_verdict.hpp"
#include "robustness/storm_core.hpp"

// The essential-function monitor in the JUnit report: a test suite of its own beside the bad-input
// classes, a test case per phase (failed when the phase lost the monitor) and one for the verdict
// (failed when DEGRADED or FAIL), so that a CI reads the monitor's outcome as it reads findings.
namespace mblab::robustness {

struct JunitSuite {
    std::string xml;  // the <testsuite> element, indented to sit in <testsuites>
    std::size_t tests = 0;
    std::size_t failures = 0;
    std::size_t skipped = 0;
};

// With the ladder's `rungs`: a test case per storm as well (classname "monitor.ladder", named by
// its key), failed when a rung lost the monitor; a storm that did not run, skipped with why.
JunitSuite monitor_junit_suite(const MonitorJudgement& judged,
                               const std::vector<LadderRung>& rungs = {},
                               const std::vector<StormNotRun>& not_run = {});

}  // namespace mblab::robustness
