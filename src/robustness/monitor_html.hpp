#pragma once

#include <string>
#include <vector>

#include "robustness/fuzz_run.hpp"
#include "robustness/monitor_verdict.hpp"
#include "robustness/storm_core.hpp"

// The monitored run as one HTML page a person reads at a glance: the monitor's latency over time
// through the phases (an inline SVG chart, missed cycles marked), the verdict, the phases' table
// with their IEC 62443-4-2 requirements, the storm ladder's table (the request storms per function
// code in a table of their own), and each finding with its reproducer. Self-contained: no script,
// no external file.
namespace mblab::robustness {

std::string monitor_html(const FuzzResult& result, const MonitorJudgement& judged,
                         const MonitorSpec& spec, const std::vector<MonitorCycle>& cycles,
                         const std::vector<LadderRung>& rungs,
                         const std::vector<StormNotRun>& not_run = {});

}  // namespace mblab::robustness
