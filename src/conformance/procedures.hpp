#pragma once

#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "conformance/pattern.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

class Session;
struct Case;
struct Dut;

// A request and its acceptable answers, for a procedure that also runs under load.
struct ProcedureStep {
    std::vector<std::uint8_t> request;
    std::vector<ResolvedPattern> expect;
};

// A check that is code rather than data: the register sweep, the SEMI scan, ping.
struct ProcedureInfo {
    std::string_view name;
    std::string_view summary;
    std::vector<std::pair<std::string_view, std::int64_t>> params;  // name, default
    std::vector<std::string_view> needs;  // DUT facts without which the case is N/A
    bool talks_modbus = true;             // needs the connection to the device
    Outcome (*run)(Session& session, const Case& c);
    // The procedure as independent exchanges for `mblab load`; none leaves it out of the loop.
    std::vector<ProcedureStep> (*load_steps)(const Dut& dut) = nullptr;
    // Opens TLS sessions of its own to the device's mbaps:// port (the security suite).
    bool needs_mbaps = false;
};

const std::vector<ProcedureInfo>& procedures();
// A procedure on the connection to the device, with no steps for `mblab load`: most of them.
ProcedureInfo modbus_procedure(std::string_view name, std::string_view summary,
                               Outcome (*run)(Session&, const Case&),
                               std::vector<std::pair<std::string_view, std::int64_t>> params = {});
const ProcedureInfo* find_procedure(std::string_view name);
// Whether `procedure` opens TLS sessions of its own (ProcedureInfo::needs_mbaps): a run that has
// one needs an mbaps:// port.
bool is_security_procedure(std::string_view procedure);

// A parameter of the case, or the procedure's default.
std::int64_t param(const Case& c, std::string_view name);

Outcome run_register_sweep(Session& session, const Case& c);
Outcome run_semi_scan(Session& session, const Case& c);
Outcome run_ping(Session& session, const Case& c);
Outcome run_out_of_range(Session& session, const Case& c);
std::vector<ProcedureStep> out_of_range_steps(const Dut& dut);

}  // namespace mblab::conformance
