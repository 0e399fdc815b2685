#include "web/typed_points.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <span>
#include <vector>

#include "device/number_codec.hpp"
#include "device/profile_loader.hpp"

namespace mblab::web {

namespace {

using device::BankKind;
using nlohmann::json;

// A range's own type as a number layout: high word first, as docs/profiles.md gives it.
std::optional<device::NumberType> range_number(device::ValueType type) {
    switch (type) {
        case device::ValueType::I16:
            return device::NumberType::I16;
        case device::ValueType::U32:
            return device::NumberType::U32;
        case device::ValueType::F32:
            return device::NumberType::F32;
        default:
            return std::nullopt;  // u16 shows as it is; bits and text are no numbers
    }
}

const device::RangeSpec* range_at(const device::UnitSpec& unit, BankKind kind,
                                  std::uint32_t address) {
    for (const auto& range : unit.banks[static_cast<std::size_t>(kind)]) {
        if (address >= range.start && address < range.start + range.count) return &range;
    }
    return nullptr;
}

struct Point {
    std::uint32_t address = 0;
    device::NumberLayout layout = {};
    bool moving = false;  // a behaviour drives it: the dashboard draws its trend
};

std::vector<Point> points_of(const device::UnitSpec& unit, BankKind kind) {
    std::vector<Point> points;
    std::vector<bool> moving(65536, false);
    for (const auto& b : unit.behaviours) {
        if (b.bank != kind || b.layout.type == device::NumberType::Bit) continue;
        const auto width = device::number_width(b.layout.type);
        for (std::uint32_t i = 0; i < b.points; ++i) {
            points.push_back({b.address + i * width, b.layout, true});
            for (std::uint32_t w = 0; w < width && b.address + i * width + w < 65536; ++w)
                moving[b.address + i * width + w] = true;
        }
    }
    for (const auto& range : unit.banks[static_cast<std::size_t>(kind)]) {
        const auto type = range_number(range.type);
        if (!type) continue;
        const auto width = device::number_width(*type);
        for (std::uint32_t a = range.start; a + width <= range.start + range.count; a += width) {
            if (!moving[a]) points.push_back({a, {*type, {}, 1.0, 0.0}, false});
        }
    }
    return points;
}

}  // namespace

json page_points(const device::ReferenceDevice& device, std::uint8_t unit, BankKind kind,
                 std::uint32_t start, std::uint32_t count) {
    json out = json::array();
    if (kind == BankKind::Coils || kind == BankKind::DiscreteInputs) return out;
    for (const auto& spec : device.declarations().profile().units) {
        if (spec.id != unit) continue;
        for (const auto& point : points_of(spec, kind)) {
            const auto width = device::number_width(point.layout.type);
            if (point.address < start || point.address + width > start + count) continue;
            const auto read = device.data().values(unit, kind, point.address, width);
            if (!read) continue;
            std::array<std::uint16_t, 4> words{};
            bool whole = true;
            for (std::uint32_t w = 0; w < width; ++w) {
                whole = whole && (*read)[w].has_value();
                words[w] = (*read)[w].value_or(0);
            }
            if (!whole) continue;
            const auto* range = range_at(spec, kind, point.address);
            out.push_back(
                {{"address", point.address},
                 {"name", range ? range->name : std::string()},
                 {"type", std::string(device::register_type_name(point.layout.type))},
                 {"order", device::order_letters(point.layout.order)},
                 {"moving", point.moving},
                 {"value", device::decode_number(std::span(words).first(width), point.layout)}});
        }
    }
    std::sort(out.begin(), out.end(),
              [](const json& a, const json& b) { return a["address"] < b["address"]; });
    return out;
}

std::string start_bank(const device::UnitSpec& unit) {
    if (!unit.behaviours.empty())
        return std::string(device::bank_key(unit.behaviours.front().bank));
    for (const auto kind : {BankKind::HoldingRegisters, BankKind::InputRegisters, BankKind::Coils,
                            BankKind::DiscreteInputs}) {
        if (!unit.banks[static_cast<std::size_t>(kind)].empty())
            return std::string(device::bank_key(kind));
    }
    return "holding_registers";
}

}  // namespace mblab::web
