#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "device/profile_loader.hpp"
#include "device/sunspec_model.hpp"

// SunSpec models from the JSON model format of the SunSpec Alliance's models repository (json/,
// its schema json/schema.json). A file that cannot be used is refused with one line:
// "FILE: GROUP.POINT: what is wrong".
namespace mblab::device {

// `source` names the text in messages.
Loaded<SunSpecModel> parse_sunspec_model(std::string_view text, std::string_view source);
Loaded<SunSpecModel> read_sunspec_model(const std::filesystem::path& path);
// Every model_*.json in `dir`, by model id.
Loaded<std::map<std::uint16_t, SunSpecModel>> read_sunspec_models(const std::filesystem::path& dir);

}  // namespace mblab::device
