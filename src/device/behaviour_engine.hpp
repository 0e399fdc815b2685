#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <vector>

#include "device/behaviour_spec.hpp"
#include "device/number_codec.hpp"
#include "support/prng.hpp"

// Moves a unit's values as its [[unit.behaviours]] say, on the clock it is given: no clock and no
// timer of its own. The owner calls advance() when deadline() comes (the server from a timer on
// its event loop, tests from a manual clock) with the device's lock held, so a request sees each
// multi-register value either before or after an update, never half of it.
namespace mblab::device {

class UnitModel;

class BehaviourEngine {
  public:
    using Clock = std::chrono::steady_clock;
    using WallClock = std::chrono::system_clock;

    BehaviourEngine(const std::vector<BehaviourSpec>& specs, std::uint64_t seed);

    bool empty() const { return behaviours_.empty(); }
    // Brings every value to `now`. The first call is the device's start (time 0). Each behaviour
    // takes the value of its last update time at or before `now`, updates falling every
    // interval from the start, so the values depend on the update times and not on how often
    // advance() is called. `wall` is the Unix time at `now`, for timestamps.
    void advance(Clock::time_point now, WallClock::time_point wall, UnitModel& unit);
    // When the next update is due: time_point::min() before the first advance(), max() when
    // there is nothing to move.
    Clock::time_point deadline() const;

  private:
    struct Sample {
        Clock::time_point at;
        std::vector<std::uint16_t> words;
    };
    struct Running {
        BehaviourSpec spec;
        Clock::time_point next_update{};
        std::vector<double> state;         // per point: random walk position, counter value
        std::vector<std::uint16_t> words;  // the points' registers as the last update left them
        Prng prng;
        std::deque<Sample> history;  // follow: the source as it was at each update
    };

    // One update at `at`, `elapsed` seconds from the start; false when it leaves the registers
    // alone (a follower whose lag has not yet passed).
    static bool update(Running& running, Clock::time_point at, double elapsed, double unix_time,
                       UnitModel& unit);
    static bool follow(Running& running, Clock::time_point at, UnitModel& unit);

    std::vector<Running> behaviours_;
    bool started_ = false;
    Clock::time_point start_{};
};

}  // namespace mblab::device
