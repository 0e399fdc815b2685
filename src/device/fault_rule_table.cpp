#include "device/fault_rule_table.hpp"

namespace mblab::device {

std::optional<std::vector<FaultSpec>> FaultRuleTable::rules(std::uint8_t id) const {
    return units_.locked([id](const UnitTable& table) -> std::optional<std::vector<FaultSpec>> {
        const UnitModel* unit = table.find(id);
        if (!unit) return std::nullopt;
        return unit->faults().rules();
    });
}

bool FaultRuleTable::set_rules(std::uint8_t id, std::vector<FaultSpec> rules) {
    return units_.locked([&](UnitTable& table) {
        UnitModel* unit = table.find(id);
        if (!unit) return false;
        unit->faults() = FaultRules(std::move(rules));
        return true;
    });
}

}  // namespace mblab::device
