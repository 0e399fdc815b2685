#pragma once

#include <string>

#include "load/plan.hpp"
#include "load/result.hpp"

namespace mblab::web {

// `mblab load --html`: the run as one self-contained page: the plan, the verdict, a table of
// every node, and per node its exchanges, its latency histogram (inline SVG) and the evidence of
// its first failure. Its figures are the JSON report's (load_json_report), read back.
std::string load_html_report(const load::LoadPlan& plan, const load::LoadResult& result);

// The node's latency distribution as an inline SVG bar chart of at most `bars` bars, each the
// answers in a run of histogram buckets, with the range in ms as the bar's tooltip.
std::string latency_svg(const load::LatencySnapshot& latency, std::size_t bars = 48);

}  // namespace mblab::web
