#pragma once

#include <vector>

#include "conformance/procedures.hpp"

// The SunSpec suite's procedures (catalogue/sunspec.toml): the chain read and judged by the
// model definitions (sunspec_cases.cpp), and the writes (sunspec_write_cases.cpp).
namespace mblab::conformance {

std::vector<ProcedureInfo> sunspec_procedures();

Outcome run_sunspec_marker(Session& session, const Case& c);
Outcome run_sunspec_common(Session& session, const Case& c);
Outcome run_sunspec_chain_end(Session& session, const Case& c);
Outcome run_sunspec_lengths(Session& session, const Case& c);
Outcome run_sunspec_unknown(Session& session, const Case& c);
Outcome run_sunspec_mandatory(Session& session, const Case& c);
Outcome run_sunspec_sentinels(Session& session, const Case& c);
Outcome run_sunspec_scale_factors(Session& session, const Case& c);
Outcome run_sunspec_enums(Session& session, const Case& c);
Outcome run_sunspec_strings(Session& session, const Case& c);
Outcome run_sunspec_accumulators(Session& session, const Case& c);
Outcome run_sunspec_chunks(Session& session, const Case& c);
Outcome run_sunspec_rw_points(Session& session, const Case& c);
Outcome run_sunspec_read_only(Session& session, const Case& c);
Outcome run_sunspec_bad_enum(Session& session, const Case& c);
Outcome run_sunspec_line(Session& session, const Case& c);

}  // namespace mblab::conformance
