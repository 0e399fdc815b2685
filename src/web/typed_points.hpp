#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "device/reference_device.hpp"

// The dashboard's values as the profile types them: each moving point (a [[unit.behaviours]]
// table) with its type and word order, and each u32, i16 or f32 range, decoded by the device's
// own number codec (device/number_codec.hpp), so an f32 in CDAB order shows as 21.53 and not as
// two registers. Named by the range that holds it.
namespace mblab::web {

// The typed points of `unit` whose registers all lie in [start, start + count) of `kind`,
// by address: {address, name, type, order, moving, value}.
nlohmann::json page_points(const device::ReferenceDevice& device, std::uint8_t unit,
                           device::BankKind kind, std::uint32_t start, std::uint32_t count);

// The bank the dashboard opens on: where the first behaviour moves values, else the first
// bank (holding, input, coils, discrete) with a range.
std::string start_bank(const device::UnitSpec& unit);

}  // namespace mblab::web
