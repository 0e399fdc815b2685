#pragma once

#include <cstdlib>
#include <filesystem>

// Where the shipped suites are. Header-only because MBLAB_SOURCE_DIR is defined for the mblab
// binary and the tests, not for the library.
namespace mblab::conformance {

inline std::filesystem::path catalogue_dir() {
    if (const char* dir = std::getenv("MBLAB_CATALOGUE_DIR"); dir && *dir) return dir;
#ifdef MBLAB_SOURCE_DIR
    const std::filesystem::path source = std::filesystem::path(MBLAB_SOURCE_DIR) / "catalogue";
    std::error_code ignored;
    if (std::filesystem::is_directory(source, ignored)) return source;
#endif
    return "/usr/local/share/mblab/catalogue";
}

}  // namespace mblab::conformance
