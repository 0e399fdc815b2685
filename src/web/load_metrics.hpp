#pragma once

#include <string>

#include "load/plan.hpp"
#include "load/runner.hpp"

// GET /metrics of `mblab load --metrics`: per node, requests sent, answers, failures, the
// answer rate and the latency histogram, as of the run's last status.
namespace mblab::web {

std::string load_metrics(const load::LoadPlan& plan, const load::LoadStatus& status);

}  // namespace mblab::web
