#pragma once

#include <string>

#include "conformance/verdict.hpp"
#include "load/plan.hpp"
#include "load/result.hpp"
#include "load/runner.hpp"

// What a load run tells its user: the plan before it starts, a status line while it runs, and
// at the end a summary table and the JSON / JUnit reports (docs/load.md describes the fields).
namespace mblab::load {

std::string load_header(const LoadPlan& plan);

// One line without line breaks or terminal codes.
std::string load_status_line(const LoadPlan& plan, const LoadStatus& status);

std::string load_summary(const LoadPlan& plan, const LoadResult& result);

std::string load_json_report(const LoadPlan& plan, const LoadResult& result);

// JUnit XML: one test case per node, a <failure> with the first failing exchange for a node
// that failed, <skipped> for a node whose run was stopped early.
std::string load_junit_report(const LoadPlan& plan, const LoadResult& result);

// The run as the conformance reports see it: a suite "load" with a case per node, its verdict
// and the evidence of its first failure.
conformance::RunResult load_as_run(const LoadPlan& plan, const LoadResult& result);

}  // namespace mblab::load
