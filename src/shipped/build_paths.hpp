#pragma once

// Paths fixed when the build was configured (cmake/build_paths.cpp.in).
namespace mblab::shipped {

extern const char* const kSourceDir;
extern const char* const kBuildDir;
extern const char* const kInstalledDataDir;

}  // namespace mblab::shipped
