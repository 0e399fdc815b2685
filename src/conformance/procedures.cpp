#include "conformance/procedures.hpp"

#include "conformance/catalogue.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

const std::vector<ProcedureInfo>& procedures() {
    static const std::vector<ProcedureInfo> list = {
        {"ping",
         "ICMP echo requests to the device's host; all must be answered (seed 000 7.2)",
         {{"count", 10}, {"payload", 32}, {"timeout_ms", 1000}},
         {},
         false,
         &run_ping,
         nullptr},
        {"register_sweep",
         "FC 03 reads of every size from 0, then in maximal blocks, then shrinking to the last "
         "register; checks length field, byte count and register count (seed 000 7.5.2)",
         {},
         {"registers"},
         true,
         &run_register_sweep,
         nullptr},
        {"semi_signature_scan",
         "FC 03 reads in blocks until 5345 4D49 5F72 appear in consecutive registers (seed 000 "
         "7.13.2)",
         {{"block", 125}},
         {},
         true,
         &run_semi_scan,
         nullptr},
        {"out_of_range_read",
         "FC 03 at 0x8001 answers 02; when 0x8001 is a register, a read past the highest one "
         "(declared count, else 2 registers from 0xFFFF) decides (seed 000 9.1.2 and its note)",
         {},
         {},
         true,
         &run_out_of_range,
         &out_of_range_steps},
    };
    return list;
}

const ProcedureInfo* find_procedure(std::string_view name) {
    for (const auto& info : procedures()) {
        if (info.name == name) return &info;
    }
    return nullptr;
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
