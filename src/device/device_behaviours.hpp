#pragma once

#include <chrono>
#include <vector>

#include "device/behaviour_engine.hpp"
#include "device/device_units.hpp"

// The values of the profile's behaviours, moved by the server's timer, never by a request. Each
// call takes the device's lock (device_units.hpp), which also guards the engines, so no request
// sees a value half-updated.
namespace mblab::device {

class DeviceBehaviours {
  public:
    explicit DeviceBehaviours(DeviceUnits& units);

    // Moves every unit's behaviours to `now` (BehaviourEngine::advance).
    void advance(std::chrono::steady_clock::time_point now,
                 std::chrono::system_clock::time_point wall);
    // When advance() is next due: min() before the first call, max() when no value moves.
    std::chrono::steady_clock::time_point deadline() const;

  private:
    DeviceUnits& units_;
    std::vector<BehaviourEngine> engines_;  // one per unit, in the same order
};

}  // namespace mblab::device
