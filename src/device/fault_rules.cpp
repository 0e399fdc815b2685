#include "device/fault_rules.hpp"

#include <algorithm>

namespace mblab::device {

bool FaultRules::matches(const FaultSpec& rule, const RequestScope& scope) {
    if (!rule.functions.empty() && std::find(rule.functions.begin(), rule.functions.end(),
                                             scope.function) == rule.functions.end()) {
        return false;
    }
    if (rule.first_address) {
        if (!scope.has_addresses) return false;
        if (scope.last < *rule.first_address || scope.first > *rule.last_address) return false;
    }
    return true;
}

const FaultSpec* FaultRules::fire(const RequestScope& scope, Prng& prng) {
    for (std::size_t i = 0; i < rules_.size(); ++i) {
        const FaultSpec& rule = rules_[i];
        if (!matches(rule, scope)) continue;
        bool fires = false;
        if (rule.every) {
            seen_[i] = (seen_[i] + 1) % rule.every;
            fires = seen_[i] == 0;
        } else {
            fires = prng.chance(rule.probability);
        }
        if (fires) return &rule;
    }
    return nullptr;
}

}  // namespace mblab::device
