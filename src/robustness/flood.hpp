#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "client/link.hpp"
#include "robustness/fuzz_case.hpp"
#include "robustness/run_clock.hpp"

// A flood: a step too large to write before its answers are read, written as the device takes it
// while the answers are read, so that a device that answers as it reads never finds its answers
// piling up unread.
namespace mblab::robustness {

// Steps larger than this are streamed.
inline constexpr std::size_t kStreamAbove = 64 * 1024;

// Streams `step` on `link` for at most twice `timeout`; returns the highest value of the
// ledger's register that an FC 06 answer acknowledged (0 when none, or no ledger).
std::uint16_t stream(client::Link& link, const Step& step, const std::optional<WriteLedger>& ledger,
                     std::chrono::milliseconds timeout, const RunClock& clock);

// The highest FC 06 value to `address` among the MBAP frames of `steps`.
std::uint16_t highest_write(const std::vector<Step>& steps, std::uint16_t address);

}  // namespace mblab::robustness
