#include "device/unit_declarations.hpp"

#include "protocol/function_code.hpp"

namespace mblab::device {

std::vector<std::uint8_t> UnitDeclarations::unit_ids() const {
    std::vector<std::uint8_t> ids;
    for (const auto& spec : profile().units)
        ids.push_back(spec.id);
    return ids;
}

std::string UnitDeclarations::addressing(Link link) const {
    const auto ids = unit_ids();
    std::string list;
    for (std::size_t i = 0; i < ids.size(); ++i)
        list += (i ? "," : "") + std::to_string(ids[i]);
    if (link == Link::Serial) {
        return (ids.size() == 1 ? "address " : "addresses ") + list +
               " (0 is a broadcast; other addresses are not answered)";
    }
    const std::string units = (ids.size() == 1 ? "unit " : "units ") + list;
    const std::string first = std::to_string(ids.front());
    std::string others = "other unit ids are not answered";
    switch (profile().unmatched_unit) {
        case UnmatchedUnit::FirstUnit:
            return units + " (0, 255 and every other unit id answer as " + first + ")";
        case UnmatchedUnit::Ignore:
            break;
        case UnmatchedUnit::PathUnavailable:
            others = "other unit ids are answered exception 0A, as by a gateway";
            break;
        case UnmatchedUnit::TargetFailed:
            others = "other unit ids are answered exception 0B, as by a gateway";
            break;
    }
    return units + " (0 and 255 answer as " + first + "; " + others + ")";
}

std::optional<UnitDeclaration> UnitDeclarations::of(std::uint8_t id) const {
    return units_.locked([id](const UnitTable& table) -> std::optional<UnitDeclaration> {
        const UnitModel* unit = table.find(id);
        if (!unit) return std::nullopt;
        const UnitSpec& spec = unit->spec();
        UnitDeclaration out;
        out.unit = spec.id;
        out.max_read_registers = spec.max_read_registers;
        out.max_read_bits = spec.max_read_bits;
        out.holding_registers = unit->bank(BankKind::HoldingRegisters).contiguous_from_zero();
        out.semi_signature = spec.semi_signature;
        out.object_messaging =
            spec.functions[static_cast<std::uint8_t>(protocol::FunctionCode::ObjectMessaging)];
        out.functions = spec.functions;
        return out;
    });
}

UnitDeclaration UnitDeclarations::first() const {
    return *of(profile().units.front().id);
}

}  // namespace mblab::device
