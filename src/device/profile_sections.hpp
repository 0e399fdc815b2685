#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "device/profile.hpp"
#include "device/toml_fields.hpp"

// Loaders for the sections of a unit, shared by profile_loader.cpp. Each reads one TOML table
// into its spec and returns false once an error has been recorded.
namespace mblab::device {

bool load_range(const toml::table& table, const std::string& path, BankKind kind,
                ProfileErrors& errors, RangeSpec& out);

// [unit.sunspec]: the SunSpec chain laid into the holding registers (sunspec_chain.hpp).
bool load_sunspec(Fields& unit, UnitSpec& spec);
bool load_identification(Fields& unit, IdentitySpec& out);
bool load_diagnostics(Fields& unit, DiagnosticsSpec& out);
bool load_server_id(Fields& unit, ServerIdSpec& out);
bool load_files(Fields& unit, std::vector<FileSpec>& out);
bool load_objects(Fields& unit, std::vector<SemiObject>& out);
bool load_faults(Fields& unit, std::vector<FaultSpec>& out);
// After the unit's banks: every behaviour's points must be mapped in them.
bool load_behaviours(Fields& unit, const UnitSpec& spec, std::vector<BehaviourSpec>& out);
bool load_roles(Fields& root, std::vector<RoleRule>& out);

// Shared value readers.
bool integer_list(Fields& fields, std::string_view key, std::int64_t min, std::int64_t max,
                  std::vector<std::int64_t>& out);
// A string (its UTF-8 bytes) or an array of byte values.
bool byte_string(Fields& fields, std::string_view key, std::size_t max_size,
                 std::vector<std::uint8_t>& out);
// Calls `load(table, path)` for each table of an array of tables under `key`.
template <class Load>
bool each_table(Fields& fields, std::string_view key, Load load) {
    const toml::array* list = nullptr;
    if (!fields.array(key, list)) return !fields.failed();
    for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string path = fields.path(key) + "[" + std::to_string(i) + "]";
        const toml::table* table = list->get(i)->as_table();
        if (!table) {
            fields.errors().fail(list->get(i)->source(), path,
                                 "expected a table, got " + describe_node(*list->get(i)));
            return false;
        }
        if (!load(*table, path)) return false;
    }
    return true;
}

}  // namespace mblab::device
