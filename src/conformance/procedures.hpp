#pragma once

#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "conformance/verdict.hpp"

namespace mblab::conformance {

class Session;
struct Case;

// A check that is code rather than data: the register sweep, the SEMI scan, ping.
struct ProcedureInfo {
    std::string_view name;
    std::string_view summary;
    std::vector<std::pair<std::string_view, std::int64_t>> params;  // name, default
    std::vector<std::string_view> needs;  // DUT facts without which the case is N/A
    bool talks_modbus = true;             // needs the connection to the device
    Outcome (*run)(Session& session, const Case& c);
};

const std::vector<ProcedureInfo>& procedures();
const ProcedureInfo* find_procedure(std::string_view name);

// A parameter of the case, or the procedure's default.
std::int64_t param(const Case& c, std::string_view name);

Outcome run_register_sweep(Session& session, const Case& c);
Outcome run_semi_scan(Session& session, const Case& c);
Outcome run_ping(Session& session, const Case& c);

}  // namespace mblab::conformance
