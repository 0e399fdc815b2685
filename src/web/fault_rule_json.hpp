#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "device/profile.hpp"

// A fault rule as the HTTP API shows and takes it: a profile's [[unit.faults]] table
// (docs/profiles.md) as JSON. The fields, limits and errors are the schema's
// (device/fault_rule_schema.hpp); this maps JSON onto it.
namespace mblab::web {

nlohmann::json fault_rule_json(const device::FaultSpec& rule);
// False with a one-line `error` naming the field when `json` is not a valid rule.
bool parse_fault_rule(const nlohmann::json& json, device::FaultSpec& rule, std::string& error);

}  // namespace mblab::web
