#pragma once

#include <chrono>
#include <cstdint>
#include <span>
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
    std::uint16_t address = 0;  // the monitor's register (the half-open storm's part request)
    // The slow readers' read: the largest the device answers, where it answers it.
    std::uint16_t large_address = 0;
    std::uint16_t large_quantity = 125;
    // How long a write storm's read of the value it writes back waits for its answer.
    std::chrono::milliseconds timeout{1000};
};

// The slow readers' requests go out in blocks of this many, one after another.
inline constexpr std::size_t kSlowReaderBlock = 100;
// The most a slow reader writes in a rung.
inline constexpr std::size_t kSlowReaderMost = std::size_t{8} << 20;

// One rung: `kind` at `rate` for `duration`; a request storm streams `request` (a PDU; empty:
// FC 03 of the monitor's register). The connections it holds (slow readers) are closed at its
// end, and the half-open ones are the device's to time out.
LadderRung storm(const StormTarget& target, StormKind kind, double rate,
                 std::chrono::milliseconds duration, std::span<const std::uint8_t> request = {});

struct Ladder {
    StormKind kind = StormKind::Fc03;
    std::vector<double> rates;
};

// The group of every request storm: `requests:RATES`, a ladder per function code.
inline constexpr const char* kRequestsGroup = "requests";

// "100,500,1000" (FC 03), or KIND:RATES with KIND a storm's key (fc01, fc03, opens,
// slow-readers, half-open, ...: storm_core.cpp's table) ("opens:10,100"): rising rates, each
// above 0; one line when not.
protocol::Result<Ladder, std::string> parse_ladder(const std::string& text);
// As parse_ladder, and `requests:RATES`: the same rates for every request storm, in the order of
// their function codes.
protocol::Result<std::vector<Ladder>, std::string> parse_ladders(const std::string& text);
// Every --ladder given, in order. A storm named twice (fc06 twice, or fc06 and `requests`) is
// refused: a storm has one verdict, and a second ladder of it would overwrite the first's.
protocol::Result<std::vector<Ladder>, std::string> parse_ladders(
    std::span<const std::string> texts);
protocol::Result<std::vector<double>, std::string> parse_rates(const std::string& text);

}  // namespace mblab::robustness
