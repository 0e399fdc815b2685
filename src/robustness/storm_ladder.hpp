#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "client/target.hpp"
#include "protocol/result.hpp"
#include "robustness/storm_core.hpp"

// The storm ladders: each storm (StormCore's kinds) run at rising rates, a rung each, for a
// while, while the essential-function monitor watches on a connection of its own; the report
// names, for each storm, the highest rate at which the monitor held and the first at which it was
// lost.
namespace mblab::robustness {

struct StormTarget {
    client::Dial dial;
    std::uint8_t unit = 1;
    std::uint16_t address = 0;  // the FC 03 storm's register (the monitor's)
    // The slow readers' read: the largest the device answers, where it answers it.
    std::uint16_t large_address = 0;
    std::uint16_t large_quantity = 125;
};

// The slow readers' requests go out in blocks of this many, one after another.
inline constexpr std::size_t kSlowReaderBlock = 100;
// The most a slow reader writes in a rung.
inline constexpr std::size_t kSlowReaderMost = std::size_t{8} << 20;

// One rung: `kind` at `rate` for `duration`. The connections it holds (slow readers) are closed
// at its end, and the half-open ones are the device's to time out.
LadderRung storm(const StormTarget& target, StormKind kind, double rate,
                 std::chrono::milliseconds duration);

struct Ladder {
    StormKind kind = StormKind::Fc03;
    std::vector<double> rates;
};

// "100,500,1000" (FC 03), or KIND:RATES with KIND fc03, opens, slow-readers or half-open
// ("opens:10,100"): rising rates, each above 0; one line when not.
protocol::Result<Ladder, std::string> parse_ladder(const std::string& text);
protocol::Result<std::vector<double>, std::string> parse_rates(const std::string& text);

}  // namespace mblab::robustness
