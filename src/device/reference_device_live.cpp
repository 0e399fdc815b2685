#include "device/reference_device.hpp"

// The device changed from outside Modbus while it serves (the HTTP API): every call takes the
// lock handle() takes, once for the whole range.
namespace mblab::device {

std::optional<std::vector<std::optional<std::uint16_t>>> ReferenceDevice::values(
    std::uint8_t id, BankKind kind, std::uint32_t start, std::uint32_t count) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    std::vector<std::optional<std::uint16_t>> out;
    out.reserve(count);
    const DataBank& bank = unit->bank(kind);
    for (std::uint32_t address = start; address < start + count; ++address) {
        const auto span = bank.find(address, 1);
        out.push_back(span.mapped ? std::optional(bank.at(span.index)) : std::nullopt);
    }
    return out;
}

bool ReferenceDevice::set_values(std::uint8_t id, BankKind kind, std::uint32_t start,
                                 std::span<const std::uint16_t> values) {
    std::lock_guard lock(mutex_);
    UnitModel* unit = find_unit(id);
    if (!unit) return false;
    DataBank& bank = unit->bank(kind);
    for (std::uint32_t i = 0; i < values.size(); ++i) {
        if (!bank.find(start + i, 1).mapped) return false;
    }
    for (std::uint32_t i = 0; i < values.size(); ++i)
        bank.at(bank.find(start + i, 1).index) = values[i];
    return true;
}

std::optional<std::vector<FaultSpec>> ReferenceDevice::fault_rules(std::uint8_t id) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    return unit->faults().rules();
}

bool ReferenceDevice::set_fault_rules(std::uint8_t id, std::vector<FaultSpec> rules) {
    std::lock_guard lock(mutex_);
    UnitModel* unit = find_unit(id);
    if (!unit) return false;
    unit->faults() = FaultRules(std::move(rules));
    return true;
}

bool ReferenceDevice::clear_counters(std::uint8_t id) {
    std::lock_guard lock(mutex_);
    UnitModel* unit = find_unit(id);
    if (!unit) return false;
    unit->comm().counters = {};
    unit->comm().event_count = 0;
    return true;
}

std::optional<std::vector<std::uint8_t>> ReferenceDevice::event_log(std::uint8_t id) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    std::vector<std::uint8_t> out(unit->comm().log.size());
    unit->comm().log.copy(out);
    return out;
}

}  // namespace mblab::device
