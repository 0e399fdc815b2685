#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "device/device_units.hpp"
#include "protocol/limits.hpp"

// What the device tells about itself before a run: its profile, the unit ids it answers and,
// per unit, what a tester is told (CTP 6.4-6.6).
namespace mblab::device {

struct UnitDeclaration {
    std::uint8_t unit = 0;
    std::uint16_t max_read_registers = protocol::limits::kMaxReadRegisters;
    std::uint16_t max_read_bits = protocol::limits::kMaxReadBits;
    // Holding registers readable from address 0 without a hole: what a 7.5.2 sweep covers.
    std::uint32_t holding_registers = 0;
    std::optional<std::uint16_t> semi_signature;  // holding address of the SEMI signature
    bool object_messaging = false;                // FC 5B served
    std::array<bool, 256> functions{};
};

class UnitDeclarations {
  public:
    explicit UnitDeclarations(const DeviceUnits& units) : units_(units) {}

    const Profile& profile() const { return units_.profile(); }
    std::vector<std::uint8_t> unit_ids() const;
    // Which unit ids (TCP) or addresses (a line) are answered, as the routing decides it: "unit
    // 1 (0 and 255 answer as 1; other unit ids are not answered)". For `mblab serve`'s banner.
    std::string addressing(Link link) const;
    // nullopt when the profile has no such unit.
    std::optional<UnitDeclaration> of(std::uint8_t unit) const;
    UnitDeclaration first() const;  // of the first unit

  private:
    const DeviceUnits& units_;
};

}  // namespace mblab::device
