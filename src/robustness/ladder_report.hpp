#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robustness/monitor_verdict.hpp"
#include "robustness/storm_core.hpp"

// The storm ladders in the report: for each storm, its rungs (rate asked, what was done, whether
// the monitor held in the rung's phase), then the highest rate at which the monitor held at every
// rung and the first at which it was lost: where the device degrades.
namespace mblab::robustness {

// The IEC 62443-4-2 requirements a storm's phases speak to.
std::string storm_requirement(StormKind kind);

// The tables, a storm after another in the order their rungs ran; "" without rungs.
std::string ladder_text(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs);
// {"rungs": [...], "storms": [{"storm", "highest_rate_held", "lost_at"}]}.
nlohmann::json ladder_json(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs);

}  // namespace mblab::robustness
