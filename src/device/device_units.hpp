#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "device/profile.hpp"
#include "device/request_handler.hpp"
#include "device/unit_model.hpp"
#include "protocol/exception_code.hpp"

// The units of a reference device and the one lock every part of the device takes
// (reference_device.hpp).
//
// Lock discipline: the units are reachable only through locked(), which holds the device's one
// mutex for the whole call it wraps. Each public call of a part (a Modbus request, a line
// event, an HTTP read or write, a behaviour step, a state snapshot) takes it exactly once and
// calls no other public call while it holds it (the mutex is not recursive). One lock rather
// than one per part, because a request touches the counters, the fault rules, the data and the
// write count in one step: with one lock each call sees the device before or after any other
// call, never between, and there is no lock order to keep.
namespace mblab::device {

// Where a request goes (routing by unit id: serial broadcast and foreign addresses, TCP unit
// 0 / 0xFF and the profile's unmatched_unit).
enum class RouteKind : std::uint8_t { Unit, Broadcast, Silent, Gateway };
struct Route {
    RouteKind kind = RouteKind::Silent;
    UnitModel* unit = nullptr;
    protocol::ExceptionCode gateway = protocol::ExceptionCode::GatewayPathUnavailable;
};

// What the lock guards.
struct UnitTable {
    explicit UnitTable(const Profile& profile);

    UnitModel* find(std::uint8_t id);
    const UnitModel* find(std::uint8_t id) const;
    Route route(const RequestContext& context);

    UnmatchedUnit unmatched = UnmatchedUnit::Ignore;
    std::vector<UnitModel> units;  // in the profile's order
    std::array<std::int16_t, 256> index{};
    // Requests that changed the writable data (coils, holding registers, file records).
    std::uint64_t state_writes = 0;
};

class DeviceUnits {
  public:
    explicit DeviceUnits(Profile profile);

    // Runs `use(table)` under the lock and returns what it returns.
    template <class Use>
    decltype(auto) locked(Use&& use) {
        std::lock_guard lock(mutex_);
        return use(table_);
    }
    template <class Use>
    decltype(auto) locked(Use&& use) const {
        std::lock_guard lock(mutex_);
        return use(std::as_const(table_));
    }

    // Set at construction and never changed, so read without the lock.
    const Profile& profile() const { return profile_; }

  private:
    Profile profile_;
    UnitTable table_;
    mutable std::mutex mutex_;
};

}  // namespace mblab::device
