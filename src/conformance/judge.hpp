#pragma once

#include <chrono>
#include <span>
#include <string>
#include <vector>

#include "client/raw_link.hpp"
#include "conformance/pattern.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

struct Judgement {
    int matched = -1;  // index of the alternative that matched, -1 for none
    Exchange exchange;
};

// Compares what came back with each expected pattern; the exchange keeps the comparison with the
// matching one, or with the closest when none matches.
Judgement judge(std::span<const std::uint8_t> sent, client::Received received,
                std::chrono::milliseconds waited, const std::vector<ResolvedPattern>& alternatives);

// One line saying what went wrong: "timeout after 1000 ms", "exception 02 (illegal data
// address)", "wrong transaction id, length field", ...
std::string describe_failure(const Exchange& exchange);

}  // namespace mblab::conformance
