#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "robustness/case_generator.hpp"
#include "robustness/recon.hpp"
#include "robustness/storm_ladder.hpp"
#include "robustness/storm_requests.hpp"

// The ladders of a monitored run, one after another: each request storm's request chosen before
// the first rung (a write's value read back just before its first rung), each storm that cannot
// run set aside with why, every rung of the others run in turn.
namespace mblab::robustness {

struct PlannedLadder {
    Ladder ladder;
    RequestPlan request;  // a request storm's; empty for a connection storm
};

struct LadderRun {
    std::vector<LadderRung> rungs;
    std::vector<StormNotRun> not_run;
};

// The ladders with their requests planned (plan_request_storm) for the monitor on register
// `monitor`.
std::vector<PlannedLadder> plan_ladders(const std::vector<Ladder>& ladders, const Recon& recon,
                                        const WritePolicy& policy, std::uint16_t monitor);

// The rungs that will run: those of the ladders not set aside already.
std::size_t rungs_to_run(const std::vector<PlannedLadder>& ladders);

// Told before each rung: the rungs done, the rungs in all (less as storms are set aside), the
// rung's phase name.
using LadderProgress =
    std::function<void(std::size_t done, std::size_t total, const std::string& phase)>;

// Runs every ladder's rungs for `step` each; a write's read is asked on a connection of its own,
// waiting the target's `timeout` for its answer.
LadderRun run_ladders(const StormTarget& target, std::vector<PlannedLadder> ladders,
                      std::chrono::milliseconds step, const LadderProgress& progress);

}  // namespace mblab::robustness
