#pragma once

#include <cstdlib>
#include <filesystem>

// Where the shipped profiles are. Header-only on purpose: MBLAB_SOURCE_DIR is defined for the
// mblab binary and the tests, not for the device library.
namespace mblab::device {

inline std::filesystem::path profiles_dir() {
    if (const char* dir = std::getenv("MBLAB_PROFILES_DIR"); dir && *dir) return dir;
#ifdef MBLAB_SOURCE_DIR
    const std::filesystem::path source = std::filesystem::path(MBLAB_SOURCE_DIR) / "profiles";
    std::error_code ignored;
    if (std::filesystem::is_directory(source, ignored)) return source;
#endif
    return "/usr/local/share/mblab/profiles";
}

inline std::filesystem::path default_profile_path() {
    return profiles_dir() / "reference.toml";
}

}  // namespace mblab::device
