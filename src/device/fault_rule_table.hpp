#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "device/device_units.hpp"

// The units' fault rules as the HTTP API reads and replaces them while the device serves; a
// request fires them (reference_device.cpp). Each call takes the device's lock once
// (device_units.hpp). nullopt / false for a unit the profile lacks.
namespace mblab::device {

class FaultRuleTable {
  public:
    explicit FaultRuleTable(DeviceUnits& units) : units_(units) {}

    std::optional<std::vector<FaultSpec>> rules(std::uint8_t unit) const;
    // Replaces the unit's rules; their "every" counts start again.
    bool set_rules(std::uint8_t unit, std::vector<FaultSpec> rules);

  private:
    DeviceUnits& units_;
};

}  // namespace mblab::device
