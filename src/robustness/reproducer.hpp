#pragma once

#include <string>
#include <vector>

#include "conformance/capture.hpp"
#include "protocol/result.hpp"
#include "robustness/fuzz_case.hpp"

// A reproducer as text `mblab fuzz TARGET --replay FILE` sends again: one step a line, the bytes
// as they go on the wire (MBAP header included) in hex, "@N" first for a connection other than
// the first, "+MSms" for the silence after it, "unread" when the connection's answers are never
// read, "vanish" when it is let go without a FIN after the bytes; '#' starts a comment.
//   # protocol-id: protocol id 0x0001
//   00 01 00 01 00 06 01 03 00 00 00 01
namespace mblab::robustness {

std::string reproducer_text(const std::vector<Step>& steps, const std::string& comment);

// The steps of a reproducer; the error names the line.
protocol::Result<std::vector<Step>, std::string> parse_reproducer(const std::string& text);

// The reproducer as a capture of one replay, for a pcap: each connection opened from 127.0.0.1
// on its first step, the steps sent with their pauses, every connection closed at the end.
// `host` is the device's IPv4 address (a name gives 0.0.0.0).
std::vector<conformance::CaptureEvent> reproducer_capture(const std::vector<Step>& steps,
                                                          const std::string& host,
                                                          std::uint16_t port);

}  // namespace mblab::robustness
