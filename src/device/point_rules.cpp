#include "device/point_rules.hpp"

#include <algorithm>

namespace mblab::device {

namespace {

using protocol::ExceptionCode;

bool cut(const PointRule& rule, std::uint32_t address, std::uint32_t count) {
    return rule.start < address || rule.start + rule.count > address + count;
}

std::uint16_t word_at(const DataBank& bank, std::uint32_t address) {
    return bank.at(bank.find(address, 1).index);
}

// The point's value once the write is done: its words from `values` where the write covers
// them, from the bank elsewhere.
std::int64_t value_after(const PointRule& rule, std::uint32_t address,
                         std::span<const std::uint16_t> values, const DataBank& bank) {
    std::uint64_t raw = 0;
    for (std::uint32_t at = rule.start; at < rule.start + rule.count; ++at) {
        const bool written = at >= address && at < address + values.size();
        raw = (raw << 16) | (written ? values[at - address] : word_at(bank, at));
    }
    if (!rule.is_signed || rule.count >= 4) return static_cast<std::int64_t>(raw);
    const unsigned bits = 16u * rule.count;
    const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
    return static_cast<std::int64_t>((raw ^ sign) - sign);
}

bool takes(const PointRule& rule, std::int64_t value) {
    if (!rule.allowed.empty() &&
        std::find(rule.allowed.begin(), rule.allowed.end(), value) == rule.allowed.end()) {
        return false;
    }
    return (!rule.min || value >= *rule.min) && (!rule.max || value <= *rule.max);
}

}  // namespace

template <class Visit>
void PointRules::overlapping(std::uint32_t address, std::uint32_t count, Visit visit) const {
    auto it = std::upper_bound(rules_.begin(), rules_.end(), address,
                               [](std::uint32_t at, const PointRule& r) { return at < r.start; });
    if (it != rules_.begin()) --it;
    for (; it != rules_.end() && it->start < address + count; ++it) {
        if (it->start + it->count > address) visit(*it);
    }
}

std::optional<ExceptionCode> PointRules::check_read(std::uint32_t address,
                                                    std::uint32_t count) const {
    std::optional<ExceptionCode> why;
    overlapping(address, count, [&](const PointRule& rule) {
        if (rule.whole && cut(rule, address, count)) why = ExceptionCode::IllegalDataAddress;
    });
    return why;
}

std::optional<ExceptionCode> PointRules::check_write(std::uint32_t address,
                                                     std::span<const std::uint16_t> values,
                                                     const DataBank& bank) const {
    const auto count = static_cast<std::uint32_t>(values.size());
    std::optional<ExceptionCode> why;
    overlapping(address, count, [&](const PointRule& rule) {
        if (why == ExceptionCode::IllegalDataAddress) return;
        if (rule.whole && cut(rule, address, count)) {
            why = ExceptionCode::IllegalDataAddress;
        } else if (!takes(rule, value_after(rule, address, values, bank))) {
            why = ExceptionCode::IllegalDataValue;
        }
    });
    return why;
}

void PointRules::keep_unapplied(std::uint32_t address, std::span<std::uint16_t> values,
                                const DataBank& bank) const {
    overlapping(address, static_cast<std::uint32_t>(values.size()), [&](const PointRule& rule) {
        if (rule.applied) return;
        for (std::uint32_t at = rule.start; at < rule.start + rule.count; ++at) {
            if (at >= address && at < address + values.size()) {
                values[at - address] = word_at(bank, at);
            }
        }
    });
}

}  // namespace mblab::device
