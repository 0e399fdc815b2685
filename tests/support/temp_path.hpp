#pragma once

#include <string>

namespace mblab::test {

// A path in the test temp directory that no other test, and no other run of this one, uses:
// CTest runs tests in parallel, so a fixed file name shared by two tests is a race.
std::string temp_path(const std::string& name);

}  // namespace mblab::test
