#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "device/profile.hpp"
#include "device/request_scope.hpp"
#include "support/prng.hpp"

// The fault rules of one unit: which rule, if any, fires for a request. Counting and chance are
// kept here so a run with the same seed and requests fires the same faults.
namespace mblab::device {

class FaultRules {
  public:
    FaultRules() = default;
    explicit FaultRules(std::vector<FaultSpec> rules)
        : rules_(std::move(rules)), seen_(rules_.size(), 0) {}

    // The first rule that matches the request and fires; rules that match but do not fire
    // still count the request (for "every").
    const FaultSpec* fire(const RequestScope& scope, Prng& prng);
    const std::vector<FaultSpec>& rules() const { return rules_; }

  private:
    static bool matches(const FaultSpec& rule, const RequestScope& scope);

    std::vector<FaultSpec> rules_;
    std::vector<std::uint32_t> seen_;
};

}  // namespace mblab::device
