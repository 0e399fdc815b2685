#pragma once

#include <cstddef>
#include <string>

#include "robustness/monitor_verdict.hpp"

// The essential-function monitor in the JUnit report: a test suite of its own beside the bad-input
// classes, a test case per phase (failed when the phase lost the monitor) and one for the verdict
// (failed when DEGRADED or FAIL), so that a CI reads the monitor's outcome as it reads findings.
namespace mblab::robustness {

struct JunitSuite {
    std::string xml;  // the <testsuite> element, indented to sit in <testsuites>
    std::size_t tests = 0;
    std::size_t failures = 0;
};

JunitSuite monitor_junit_suite(const MonitorJudgement& judged);

}  // namespace mblab::robustness
