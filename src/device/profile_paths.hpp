#pragma once

#include <cstdlib>
#include <filesystem>

// Where shipped data (profiles, catalogues) is. Header-only on purpose: MBLAB_SOURCE_DIR is defined
// for the mblab binary and the tests, not for the libraries.
namespace mblab::device {

// $env_var if set, else <source tree>/<name> when it exists, else the install location.
inline std::filesystem::path shipped_dir(const char* env_var, const char* name) {
    if (const char* dir = std::getenv(env_var); dir && *dir) return dir;
#ifdef MBLAB_SOURCE_DIR
    const std::filesystem::path source = std::filesystem::path(MBLAB_SOURCE_DIR) / name;
    std::error_code ignored;
    if (std::filesystem::is_directory(source, ignored)) return source;
#endif
    return std::filesystem::path("/usr/local/share/mblab") / name;
}

inline std::filesystem::path profiles_dir() {
    return shipped_dir("MBLAB_PROFILES_DIR", "profiles");
}

inline std::filesystem::path default_profile_path() {
    return profiles_dir() / "reference.toml";
}

}  // namespace mblab::device
