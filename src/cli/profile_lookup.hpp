#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace mblab::cli {

// A profile given as a file, or by the name of a shipped one ("reference"), as `serve` and
// `conform --profile` take it. nullopt with `error` naming the shipped profiles otherwise.
std::optional<std::filesystem::path> find_profile(const std::string& wanted, std::string& error);

}  // namespace mblab::cli
