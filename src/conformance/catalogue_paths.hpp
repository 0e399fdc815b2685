#pragma once

#include <filesystem>

#include "shipped/data_dir.hpp"

namespace mblab::conformance {

inline std::filesystem::path catalogue_dir() {
    return shipped::data_dir("MBLAB_CATALOGUE_DIR", "catalogue");
}

}  // namespace mblab::conformance
