#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "device/data_bank.hpp"
#include "device/profile.hpp"
#include "protocol/exception_code.hpp"

// The holding-register points a unit checks (PointRule in profile.hpp): whole multi-register
// points and the values a write may leave in a point.
namespace mblab::device {

class PointRules {
  public:
    PointRules() = default;
    explicit PointRules(std::vector<PointRule> rules) : rules_(std::move(rules)) {}

    bool empty() const { return rules_.empty(); }

    // 02 when [address, address + count) takes part of a point that is read whole.
    std::optional<protocol::ExceptionCode> check_read(std::uint32_t address,
                                                      std::uint32_t count) const;
    // 02 when the write takes part of a point written whole, 03 when it leaves a point outside
    // its values; `bank` holds the words the write does not replace.
    std::optional<protocol::ExceptionCode> check_write(std::uint32_t address,
                                                       std::span<const std::uint16_t> values,
                                                       const DataBank& bank) const;
    // Puts the bank's words back in `values` where a point does not apply writes.
    void keep_unapplied(std::uint32_t address, std::span<std::uint16_t> values,
                        const DataBank& bank) const;

  private:
    // Calls visit(rule) for each rule overlapping [address, address + count).
    template <class Visit>
    void overlapping(std::uint32_t address, std::uint32_t count, Visit visit) const;

    std::vector<PointRule> rules_;
};

}  // namespace mblab::device
