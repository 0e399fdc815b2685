#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "conformance/verdict.hpp"

// A suite's cases as an HTML table, shared by the conform report and the load report (whose
// nodes are the cases of its suite "load").
namespace mblab::web {

// The verdict as a CSS class name: PASS, FAIL, NA, NOTRUN.
std::string_view verdict_class(conformance::Verdict verdict);

// An exchange as the console shows it (conformance::evidence_layout), with the bytes that differ
// from the expected ones marked <mark class="diff"> in the received and the expected lines, which
// take the place of the ^^ line.
std::string evidence_html(const conformance::Exchange& exchange);

// A table with a <tbody class="case"> per case (id, verdict, title, reason, source and the
// evidence of a failure), carrying data-verdict and data-id for the page's filters. `more`, when
// given, adds a case's own evidence (HTML) under it: conform-client's wire transcript.
std::string case_table(const conformance::SuiteResult& suite,
                       const std::function<std::string(const conformance::CaseResult&)>& more = {});

// The checkboxes per verdict, the search box by case id and the count of cases shown.
std::string case_filters();

}  // namespace mblab::web
