#include "device/profile_sections.hpp"

// [[role]] tables: the Modbus/TCP Security rights of each role (docs/security.md).
namespace mblab::device {

bool load_roles(Fields& root, std::vector<RoleRule>& out) {
    return each_table(root, "role", [&](const toml::table& t, const std::string& path) {
        Fields fields(t, path, root.errors());
        RoleRule rule;
        if (!fields.require("name",
                            "the role as certificates carry it, e.g. name = \"Operator\"")) {
            return false;
        }
        fields.string("name", rule.role);
        if (!fields.failed() && rule.role.empty()) {
            fields.fail("name", "a role name cannot be empty");
            return false;
        }
        std::vector<std::int64_t> list;
        if (integer_list(fields, "functions", 1, 0x7F, list)) {
            rule.functions.assign(list.begin(), list.end());
        }
        fields.choice<RoleAccess>(
            "access", rule.access,
            {{"any", RoleAccess::Any}, {"read", RoleAccess::Read}, {"write", RoleAccess::Write}});
        list.clear();
        if (integer_list(fields, "units", 0, 0xFF, list))
            rule.units.assign(list.begin(), list.end());
        std::int64_t first = 0;
        std::int64_t last = 0;
        if (integer_pair(fields, "addresses", 0, 0xFFFF, first, last)) {
            rule.first_address = static_cast<std::uint16_t>(first);
            rule.last_address = static_cast<std::uint16_t>(last);
        }
        fields.finish();
        if (fields.failed()) return false;
        out.push_back(std::move(rule));
        return true;
    });
}

}  // namespace mblab::device
