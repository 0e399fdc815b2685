#pragma once

#include <filesystem>

#include "device/profile_paths.hpp"

namespace mblab::conformance {

inline std::filesystem::path catalogue_dir() {
    return device::shipped_dir("MBLAB_CATALOGUE_DIR", "catalogue");
}

}  // namespace mblab::conformance
