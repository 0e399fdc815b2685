#include "device/device_behaviours.hpp"

#include <algorithm>

namespace mblab::device {

DeviceBehaviours::DeviceBehaviours(DeviceUnits& units) : units_(units) {
    const Profile& profile = units.profile();
    for (const auto& spec : profile.units) {
        // Units draw apart: the same behaviours on two units do not move in step.
        engines_.emplace_back(spec.behaviours, profile.behaviour_seed ^ (spec.id * 0x100000001ULL));
    }
}

void DeviceBehaviours::advance(std::chrono::steady_clock::time_point now,
                               std::chrono::system_clock::time_point wall) {
    units_.locked([&](UnitTable& table) {
        for (std::size_t i = 0; i < table.units.size(); ++i)
            engines_[i].advance(now, wall, table.units[i]);
    });
}

std::chrono::steady_clock::time_point DeviceBehaviours::deadline() const {
    return units_.locked([this](const UnitTable&) {
        auto next = std::chrono::steady_clock::time_point::max();
        for (const auto& engine : engines_)
            next = std::min(next, engine.deadline());
        return next;
    });
}

}  // namespace mblab::device
