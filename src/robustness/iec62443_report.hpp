#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/result.hpp"
#include "robustness/fuzz_case.hpp"
#include "robustness/monitor_verdict.hpp"

// A robustness run with the essential-function monitor, in the terms of IEC 62443-4-2: each
// phase and each finding tagged with the component requirement it speaks to (CR 3.5 input
// validation, CR 3.6 deterministic output, CR 7.1 denial-of-service protection, CR 7.2 resource
// management), the verdict, and what the run leaves out.
namespace mblab::robustness {

// What a Modbus tester cannot reach, said in every report.
inline constexpr std::string_view kOutOfScope =
    "Ethernet, ARP, IP and ICMP storms (below Modbus/TCP: a network load tester's)";

// The requirements a class's finding speaks to: "CR 3.5 input validation" for malformed frames,
// "CR 7.1 denial-of-service protection; CR 7.2 resource management" for the resource classes,
// "CR 3.6 deterministic output" added for floods (an acknowledged write lost).
std::string requirement_of(BadInput kind);

// "register=N,period=MS,budget=MS,miss=PERCENT" (any of them, in any order; "read-only" for the
// read alone) over the defaults in `spec`. One line on a bad key or value.
protocol::Result<MonitorSpec, std::string> parse_monitor_spec(const std::string& text,
                                                              MonitorSpec spec);

// The phases' lines, the verdict with its reason, and the out-of-scope line.
std::string monitor_text(const MonitorJudgement& judged, const MonitorSpec& spec);
// The same for the JSON report, with every cycle (its start from the run's first, in ms, and
// its latency in µs or why it missed).
nlohmann::json monitor_json(const MonitorJudgement& judged, const MonitorSpec& spec,
                            const std::vector<MonitorCycle>& cycles);

}  // namespace mblab::robustness
