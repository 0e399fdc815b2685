#pragma once

#include <string>
#include <vector>

#include "conformance/verdict.hpp"

namespace mblab::conformance {

// The lines that show a failed exchange: bytes sent, bytes received (or why none), the expected
// pattern, and a line of ^^ under each byte that differs. Shared by the console and JUnit.
std::vector<std::string> evidence_lines(const Exchange& exchange);

// "0.42 s" / "1.3 ms"
std::string format_duration(std::chrono::microseconds elapsed);

// "unit 1, 65536 registers, max read 125, object messaging: yes, alternate encoding: no"
std::string describe_dut(const Dut& dut);

}  // namespace mblab::conformance
