#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "conformance/verdict.hpp"

namespace mblab::conformance {

// A run of at least this many identical bytes shows as one cell, "5A x246": a 250-byte frame of
// padding then fits a line and the bytes around it stay readable. The JSON report and the pcap
// keep every byte.
inline constexpr std::size_t kShortestRun = 8;

// `bytes` as hex cells, each run of kShortestRun or more identical bytes as "5A x246".
std::string compact_hex(std::span<const std::uint8_t> bytes);

// One line of evidence and the columns [first, last) in it that show bytes that differ from
// the expected ones.
struct EvidenceLine {
    std::string text;
    std::vector<std::pair<std::size_t, std::size_t>> marked = {};
};

// The lines that show a failed exchange: bytes sent, bytes received (or why none), the expected
// pattern, and a line of ^^ under each byte that differs. Runs are compacted (compact_hex); the
// received and expected lines are laid out cell for cell, so a differing byte sits at the same
// column in both and the ^^ line under them. Shared by the console, the HTML report and JUnit.
std::vector<EvidenceLine> evidence_layout(const Exchange& exchange);
// The same, text only.
std::vector<std::string> evidence_lines(const Exchange& exchange);

// Evidence lines cut to `width` columns: the received, expected and ^^ lines are cut at the same
// columns (between cells), so each piece of ^^ stays under its bytes; a continuation is indented
// to the column the bytes start at. Width 0 leaves the lines whole.
std::vector<std::string> wrap_evidence(const std::vector<std::string>& lines, std::size_t width);

// "0.42 s" / "1.3 ms"
std::string format_duration(std::chrono::microseconds elapsed);

// "unit 1, 65536 registers, max read 125, object messaging: yes, alternate encoding: no"
std::string describe_dut(const Dut& dut);

}  // namespace mblab::conformance
