#pragma once

#include <filesystem>

#include "shipped/data_dir.hpp"

// Where shipped data (profiles, catalogues) is; the lookup order is in shipped/data_dir.hpp.
namespace mblab::device {

inline std::filesystem::path shipped_dir(const char* env_var, const char* name) {
    return shipped::data_dir(env_var, name);
}

inline std::filesystem::path profiles_dir() {
    return shipped_dir("MBLAB_PROFILES_DIR", "profiles");
}

// The SunSpec model definitions: the official set a user points at with MBLAB_SUNSPEC_MODELS
// (or --sunspec-models), else the project's own definitions of the models it serves.
inline std::filesystem::path sunspec_models_dir() {
    return shipped_dir("MBLAB_SUNSPEC_MODELS", "sunspec");
}

inline std::filesystem::path default_profile_path() {
    return profiles_dir() / "reference.toml";
}

}  // namespace mblab::device
