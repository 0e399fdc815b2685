#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string_view>

#include "device/device_behaviours.hpp"
#include "device/device_state.hpp"
#include "device/device_units.hpp"
#include "device/fault_rule_table.hpp"
#include "device/line_counters.hpp"
#include "device/profile.hpp"
#include "device/profile_loader.hpp"
#include "device/request_handler.hpp"
#include "device/unit_data.hpp"
#include "device/unit_declarations.hpp"
#include "support/prng.hpp"

// The reference device: a profile's units behind the RequestHandler seam. handle() routes by
// unit id (serial broadcast and foreign addresses, TCP unit 0 / 0xFF), applies listen-only mode
// and the fault rules, serves the request in [APP]'s check order (function 01, values 03, map 02,
// execution 04), encodes the answer and keeps the FC 08 / 0B / 0C counters and log.
//
// What is reached without Modbus is in parts named for what they hold, each over the same units
// and the same lock (device_units.hpp has the lock discipline): data() the data tables,
// counters() the line and diagnostic counters, faults() the fault rules, declarations() what a
// tester is told, state() the writable data as a whole and its journal replay, behaviours() the
// values that move by themselves. Several sessions and the HTTP API may share one device.
namespace mblab::device {

class ReferenceDevice final : public RequestHandler {
  public:
    explicit ReferenceDevice(Profile profile);

    Reply handle(const RequestContext& context, std::span<const std::uint8_t> request,
                 std::span<std::uint8_t> response) override;

    UnitData& data() { return data_; }
    const UnitData& data() const { return data_; }
    LineCounters& counters() { return counters_; }
    const LineCounters& counters() const { return counters_; }
    FaultRuleTable& faults() { return faults_; }
    const FaultRuleTable& faults() const { return faults_; }
    const UnitDeclarations& declarations() const { return declarations_; }
    DeviceState& state() { return state_; }
    const DeviceState& state() const { return state_; }
    DeviceBehaviours& behaviours() { return behaviours_; }

  private:
    Reply serve(UnitTable& table, UnitModel& unit, std::span<const std::uint8_t> request,
                std::span<std::uint8_t> response, bool broadcast);
    Reply answer(UnitModel& unit, std::uint8_t function, const MaybeResponse& outcome,
                 std::span<std::uint8_t> response, bool counts_as_event);
    Reply garbage(std::size_t size, std::span<std::uint8_t> response);

    DeviceUnits units_;
    UnitData data_{units_};
    LineCounters counters_{units_};
    FaultRuleTable faults_{units_};
    UnitDeclarations declarations_{units_};
    DeviceState state_{units_};
    DeviceBehaviours behaviours_{units_};
    // The request path's own, under the same lock: the draws of fault chances and garbage, and
    // the response data a decoded request's outcome points into.
    Prng prng_;
    std::array<std::uint8_t, 256> scratch_{};
};

Loaded<std::unique_ptr<ReferenceDevice>> load_profile(const std::filesystem::path& path);
Loaded<std::unique_ptr<ReferenceDevice>> load_profile_text(std::string_view text,
                                                           std::string_view name);

}  // namespace mblab::device
