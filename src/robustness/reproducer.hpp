#pragma once

#include <string>
#include <vector>

#include "protocol/result.hpp"
#include "robustness/fuzz_case.hpp"

// A reproducer as text `mblab fuzz TARGET --replay FILE` sends again: one step a line, the bytes
// as they go on the wire (MBAP header included) in hex, "@N" first for a connection other than
// the first, "+MSms" last for the silence after it; '#' starts a comment.
//   # protocol-id: protocol id 0x0001
//   00 01 00 01 00 06 01 03 00 00 00 01
namespace mblab::robustness {

std::string reproducer_text(const std::vector<Step>& steps, const std::string& comment);

// The steps of a reproducer; the error names the line.
protocol::Result<std::vector<Step>, std::string> parse_reproducer(const std::string& text);

}  // namespace mblab::robustness
