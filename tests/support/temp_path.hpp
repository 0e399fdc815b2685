#pragma once

#include <string>

namespace mblab::test {

// A path in the test temp directory that no other test, and no other run of this one, uses:
// CTest runs tests in parallel, so a fixed file name shared by two tests is a race.
// Whatever is at the path when the test ends is removed if the test passed; a failed test's
// files stay for the person reading the failure, and the test's output names them.
std::string temp_path(const std::string& name);

}  // namespace mblab::test
