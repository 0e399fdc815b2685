#include "device/role_rules.hpp"

#include <algorithm>

#include "device/request_scope.hpp"
#include "protocol/function_table.hpp"

namespace mblab::device {

namespace {

bool contains(const std::vector<std::uint8_t>& list, std::uint8_t value) {
    return list.empty() || std::find(list.begin(), list.end(), value) != list.end();
}

bool access_allows(RoleAccess access, std::uint8_t function) {
    if (access == RoleAccess::Any) return true;
    const protocol::FunctionRow* row = protocol::find_function(function);
    // A code outside the table may do anything: only an explicit "any" rule lets it through.
    if (!row) return false;
    const bool writes = row->writes == protocol::Writes::Yes;
    return access == RoleAccess::Write ? writes : !writes;
}

bool addresses_allowed(const RoleRule& rule, std::span<const std::uint8_t> pdu) {
    if (!rule.first_address && !rule.last_address) return true;
    const protocol::FunctionRow* row = protocol::find_function(pdu.front());
    // A code outside the table names addresses nobody can tell: it cannot pass a range.
    if (!row) return false;
    if (row->scope == protocol::AddressScope::None) return true;
    const auto scope = scope_of(pdu.front(), protocol::decode_request(pdu));
    if (!scope.has_addresses) return false;
    const std::uint32_t first = rule.first_address.value_or(0);
    const std::uint32_t last = rule.last_address.value_or(0xFFFF);
    return scope.first >= first && scope.last <= last;
}

}  // namespace

bool RoleRules::permits(const std::optional<std::string>& role, std::uint8_t unit,
                        std::span<const std::uint8_t> pdu) const {
    if (!role || pdu.empty()) return false;
    const std::uint8_t function = pdu.front();
    return std::any_of(rules_.begin(), rules_.end(), [&](const RoleRule& rule) {
        return rule.role == *role && contains(rule.functions, function) &&
               access_allows(rule.access, function) && contains(rule.units, unit) &&
               addresses_allowed(rule, pdu);
    });
}

bool RoleRules::has_role(std::string_view role) const {
    return std::any_of(rules_.begin(), rules_.end(),
                       [&](const RoleRule& rule) { return rule.role == role; });
}

}  // namespace mblab::device
