#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "device/device_units.hpp"

// The units' data tables read and written without Modbus: by the CLI, the tests, and the HTTP
// API (src/web) while the device serves. Each call takes the device's lock once for its whole
// range, so a request sees a range either before or after it (device_units.hpp). nullopt / false
// for a unit the profile lacks; a hole reads as nullopt and makes a write refused whole.
namespace mblab::device {

class UnitData {
  public:
    explicit UnitData(DeviceUnits& units) : units_(units) {}

    std::optional<std::uint16_t> value(std::uint8_t unit, BankKind kind,
                                       std::uint16_t address) const;
    bool set_value(std::uint8_t unit, BankKind kind, std::uint16_t address, std::uint16_t value);
    std::optional<std::vector<std::optional<std::uint16_t>>> values(std::uint8_t unit,
                                                                    BankKind kind,
                                                                    std::uint32_t start,
                                                                    std::uint32_t count) const;
    bool set_values(std::uint8_t unit, BankKind kind, std::uint32_t start,
                    std::span<const std::uint16_t> values);

  private:
    DeviceUnits& units_;
};

}  // namespace mblab::device
