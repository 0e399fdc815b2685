#include "device/unit_data.hpp"

namespace mblab::device {

std::optional<std::uint16_t> UnitData::value(std::uint8_t id, BankKind kind,
                                             std::uint16_t address) const {
    const auto read = values(id, kind, address, 1);
    return read ? read->front() : std::nullopt;
}

bool UnitData::set_value(std::uint8_t id, BankKind kind, std::uint16_t address,
                         std::uint16_t value) {
    return set_values(id, kind, address, std::span(&value, 1));
}

std::optional<std::vector<std::optional<std::uint16_t>>> UnitData::values(
    std::uint8_t id, BankKind kind, std::uint32_t start, std::uint32_t count) const {
    return units_.locked(
        [&](const UnitTable& table) -> std::optional<std::vector<std::optional<std::uint16_t>>> {
            const UnitModel* unit = table.find(id);
            if (!unit) return std::nullopt;
            std::vector<std::optional<std::uint16_t>> out;
            out.reserve(count);
            const DataBank& bank = unit->bank(kind);
            for (std::uint32_t address = start; address < start + count; ++address) {
                const auto span = bank.find(address, 1);
                out.push_back(span.mapped ? std::optional(bank.at(span.index)) : std::nullopt);
            }
            return out;
        });
}

bool UnitData::set_values(std::uint8_t id, BankKind kind, std::uint32_t start,
                          std::span<const std::uint16_t> values) {
    return units_.locked([&](UnitTable& table) {
        UnitModel* unit = table.find(id);
        if (!unit) return false;
        DataBank& bank = unit->bank(kind);
        for (std::uint32_t i = 0; i < values.size(); ++i) {
            if (!bank.find(start + i, 1).mapped) return false;
        }
        for (std::uint32_t i = 0; i < values.size(); ++i)
            bank.at(bank.find(start + i, 1).index) = values[i];
        return true;
    });
}

}  // namespace mblab::device
