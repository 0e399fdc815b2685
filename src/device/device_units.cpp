#include "device/device_units.hpp"

namespace mblab::device {

namespace {
constexpr std::uint8_t kTcpDirectUnit = 0xFF;
}  // namespace

UnitTable::UnitTable(const Profile& profile) : unmatched(profile.unmatched_unit) {
    index.fill(-1);
    units.reserve(profile.units.size());
    for (const auto& spec : profile.units) {
        index[spec.id] = static_cast<std::int16_t>(units.size());
        units.emplace_back(spec);
    }
}

UnitModel* UnitTable::find(std::uint8_t id) {
    const auto i = index[id];
    return i < 0 ? nullptr : &units[static_cast<std::size_t>(i)];
}

const UnitModel* UnitTable::find(std::uint8_t id) const {
    const auto i = index[id];
    return i < 0 ? nullptr : &units[static_cast<std::size_t>(i)];
}

Route UnitTable::route(const RequestContext& context) {
    using protocol::ExceptionCode;
    if (UnitModel* unit = find(context.unit)) return {RouteKind::Unit, unit};
    if (context.link == Link::Serial) {
        return {context.unit == 0 ? RouteKind::Broadcast : RouteKind::Silent, nullptr};
    }
    if (context.unit == 0 || context.unit == kTcpDirectUnit)
        return {RouteKind::Unit, &units.front()};
    switch (unmatched) {
        case UnmatchedUnit::FirstUnit:
            return {RouteKind::Unit, &units.front()};
        case UnmatchedUnit::Ignore:
            return {RouteKind::Silent, nullptr};
        case UnmatchedUnit::PathUnavailable:
            return {RouteKind::Gateway, nullptr, ExceptionCode::GatewayPathUnavailable};
        case UnmatchedUnit::TargetFailed:
            return {RouteKind::Gateway, nullptr, ExceptionCode::GatewayTargetFailedToRespond};
    }
    return {};
}

DeviceUnits::DeviceUnits(Profile profile) : profile_(std::move(profile)), table_(profile_) {
    // The units hold the data now.
    for (auto& spec : profile_.units)
        spec = table_.find(spec.id)->spec();
}

}  // namespace mblab::device
