#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robustness/monitor_verdict.hpp"
#include "robustness/storm_core.hpp"

// The storm ladders in the report: for each storm, its rungs (rate asked, what was done, whether
// the monitor held in the rung's phase), then the highest rate at which the monitor held at every
// rung and the first at which it was lost: where the device degrades. The request storms are
// summed up again per function code, with the storms asked for that could not run and why.
namespace mblab::robustness {

// The IEC 62443-4-2 requirements a storm's phases speak to.
std::string storm_requirement(StormKind kind);
// The same, short: "CR 7.1", "CR 7.1, CR 7.2".
std::string storm_tag(StormKind kind);

struct StormSummary {
    StormKind kind = StormKind::Fc03;
    std::optional<double> highest_held;  // held at every rung up to it
    std::optional<double> lost_at;       // the first rung that lost the monitor
};

// One summary per storm, in the order they ran.
std::vector<StormSummary> storm_summaries(const MonitorJudgement& judged,
                                          const std::vector<LadderRung>& rungs);
// "held up to 500 requests/s, lost at 1000/s", "lost from the first rung (100 requests/s)".
std::string summary_words(const StormSummary& summary);

// The tables, a storm after another in the order their rungs ran, then the request storms per
// function code (those not run among them); "" without rungs or storms set aside.
std::string ladder_text(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                        const std::vector<StormNotRun>& not_run = {});
// {"rungs": [...], "storms": [{"storm", "function" (request storms), "requirement",
// "highest_rate_held", "lost_at"}], "not_run": [{"storm", "function", "reason"}]}.
nlohmann::json ladder_json(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                           const std::vector<StormNotRun>& not_run = {});

}  // namespace mblab::robustness
