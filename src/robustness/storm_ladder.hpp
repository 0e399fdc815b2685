#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "client/target.hpp"
#include "protocol/result.hpp"
#include "robustness/run_clock.hpp"

// The storm rate ladder: the known-good read streamed on a connection of its own at rising rates,
// each rung for a while, its answers read as they come and never waited for, while the
// essential-function monitor watches; the report names the highest rate at which it held.
namespace mblab::robustness {

struct LadderRung {
    double rate = 0;  // requests per second asked for
    Clock::time_point begin{};
    Clock::time_point end{};
    std::size_t sent = 0;
    std::size_t answered = 0;
    std::size_t reconnects = 0;  // the device closed the storm's connection
};

// FC 03 of one register at `address` to `unit`, `rate` times a second for `duration`.
LadderRung storm(const client::Dial& dial, std::uint8_t unit, std::uint16_t address, double rate,
                 std::chrono::milliseconds duration);

// "100,500,1000": rising rates, each above 0; one line when not.
protocol::Result<std::vector<double>, std::string> parse_rates(const std::string& text);

}  // namespace mblab::robustness
