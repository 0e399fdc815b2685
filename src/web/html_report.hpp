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

}  // namespace mblab::web
