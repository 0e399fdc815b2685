#pragma once

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "client/target.hpp"
#include "protocol/result.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/fuzz_run.hpp"
#include "robustness/ladder_run.hpp"
#include "robustness/monitor_junit.hpp"
#include "robustness/monitor_run.hpp"
#include "robustness/monitor_verdict.hpp"

// `mblab fuzz --monitor`: the essential-function monitor beside the run, through its phases
// (baseline, malformed input, recovery), judged PASS, DEGRADED or FAIL (docs/robustness.md).
namespace mblab::cli {

struct MonitorChoice {
    std::string spec;  // --monitor's text; "" for none
    double baseline_s = 2;
    double degraded_limit_s = 10;
    std::vector<std::string> ladder;  // each --ladder: a storm's rates
    double ladder_step_s = 2;
};

class FuzzMonitor {
  public:
    // Why the monitor's spec or a ladder is wrong, checked before connecting (the spec's
    // defaults come from reconnaissance); "" when nothing is.
    static std::string check(const MonitorChoice& choice);
    // Nothing when no monitor was asked for; one line when the spec is wrong, the target is a
    // serial line, or the register may not be written under `policy`.
    static protocol::Result<std::unique_ptr<FuzzMonitor>, std::string> make(
        const MonitorChoice& choice, const client::Target& target, const robustness::Recon& recon,
        const robustness::WritePolicy& policy, std::chrono::milliseconds timeout);

    // Starts the monitor and keeps it alone for the baseline.
    void baseline();
    // The storm ladders' rungs, each a phase, after the baseline; on a terminal (`live`), a
    // progress line before each rung.
    void ladder(bool live);
    void malformed_begin();
    // After the last case: the monitor alone until it holds again (or the degraded limit has
    // passed), and a few periods more; then it stops.
    void recover();
    robustness::MonitorJudgement judge(const robustness::FuzzResult& result) const;
    std::string text(const robustness::MonitorJudgement& judged) const;
    nlohmann::json json(const robustness::MonitorJudgement& judged) const;
    std::string html(const robustness::FuzzResult& result,
                     const robustness::MonitorJudgement& judged) const;
    robustness::JunitSuite junit(const robustness::MonitorJudgement& judged) const;

    FuzzMonitor(robustness::MonitorSpec spec, robustness::StormTarget storms,
                const MonitorChoice& choice, std::vector<robustness::PlannedLadder> ladders);

  private:
    robustness::MonitorSpec spec_;
    robustness::StormTarget storms_;
    robustness::MonitorRun run_;
    std::vector<robustness::PlannedLadder> ladders_;
    std::chrono::milliseconds ladder_step_;
    robustness::LadderRun ladder_;
    std::chrono::milliseconds baseline_;
    std::chrono::milliseconds degraded_limit_;
    std::vector<robustness::MonitorPhase> phases_;
    std::vector<robustness::MonitorCycle> cycles_;  // once stopped
};

}  // namespace mblab::cli
