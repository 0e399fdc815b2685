#pragma once

#include <string>

#include "conformance/provenance.hpp"
#include "conformance/verdict.hpp"

namespace mblab::web {

// `mblab conform --html`: the run as one self-contained page from the data the JSON report takes
// (summary, the DUT's declarations and their sources, the device's identity, provenance, every
// case and the evidence of failures), with filters by verdict and a search by case id.
std::string conform_html_report(const conformance::RunResult& result,
                                const conformance::Provenance& provenance);

// The parts every report of a run shares (conform's and conform-client's): the outcome banner
// (#outcome), the counts (#summary) and the provenance table (#provenance).
std::string outcome_banner(const conformance::RunResult& result);
std::string summary_table(const conformance::RunResult& result);
std::string provenance_table(const conformance::Provenance& provenance);

}  // namespace mblab::web
