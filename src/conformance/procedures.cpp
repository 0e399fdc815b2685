#include "conformance/procedures.hpp"

#include "conformance/catalogue.hpp"
#include "conformance/security_cases.hpp"
#include "conformance/serial_line_cases.hpp"
#include "conformance/sunspec_cases.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

namespace {

// The suites' own procedures after the general ones, in the catalogue's order.
std::vector<ProcedureInfo> with_suites(std::vector<ProcedureInfo> list) {
    for (auto suite : {serial_line_procedures(), line_timing_procedures(), security_procedures(),
                       sunspec_procedures()}) {
        list.insert(list.end(), suite.begin(), suite.end());
    }
    return list;
}

}  // namespace

const std::vector<ProcedureInfo>& procedures() {
    static const std::vector<ProcedureInfo> list = with_suites({
        {"ping",
         "ICMP echo requests to the device's host; all must be answered (CTP 7.2)",
         {{"count", 10}, {"payload", 32}, {"timeout_ms", 1000}},
         {},
         false,
         &run_ping,
         nullptr},
        {"register_sweep",
         "FC 03 reads of every size from 0, then in maximal blocks, then shrinking to the last "
         "register; checks length field, byte count and register count (CTP 7.5.2)",
         {},
         {"registers"},
         true,
         &run_register_sweep,
         nullptr},
        {"semi_signature_scan",
         "FC 03 reads in blocks until 5345 4D49 5F72 appear in consecutive registers (CTP "
         "7.13.2)",
         {{"block", 125}},
         {},
         true,
         &run_semi_scan,
         nullptr},
        {"out_of_range_read",
         "FC 03 at 0x8001 answers 02; when 0x8001 is a register, a read past the highest one "
         "(declared count, else 2 registers from 0xFFFF) decides (CTP 9.1.2 and its note)",
         {},
         {},
         true,
         &run_out_of_range,
         &out_of_range_steps},
    });
    return list;
}

const ProcedureInfo* find_procedure(std::string_view name) {
    for (const auto& info : procedures()) {
        if (info.name == name) return &info;
    }
    return nullptr;
}

bool is_security_procedure(std::string_view procedure) {
    const ProcedureInfo* info = find_procedure(procedure);
    return info != nullptr && info->needs_mbaps;
}

ProcedureInfo modbus_procedure(std::string_view name, std::string_view summary,
                               Outcome (*run)(Session&, const Case&),
                               std::vector<std::pair<std::string_view, std::int64_t>> params) {
    return ProcedureInfo{name, summary, std::move(params), {}, true, run, nullptr, false};
}

std::int64_t param(const Case& c, std::string_view name) {
    if (auto it = c.params.find(std::string(name)); it != c.params.end()) return it->second;
    if (const ProcedureInfo* info = find_procedure(c.procedure)) {
        for (const auto& [key, value] : info->params) {
            if (key == name) return value;
        }
    }
    return 0;
}

}  // namespace mblab::conformance
