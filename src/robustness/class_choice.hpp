#pragma once

#include <array>
#include <string>
#include <vector>

#include "protocol/result.hpp"
#include "robustness/fuzz_case.hpp"

// Which bad-input classes a run tries (`mblab fuzz --class`, `--skip-class`).
namespace mblab::robustness {

using ClassChoice = std::array<bool, kBadInputCount>;  // indexed by BadInput

// Every class, less those skipped; with `only` not empty, those classes alone (less those
// skipped). Each entry may hold several names separated by commas. An unknown name fails with one
// line that names the option and lists the classes there are.
protocol::Result<ClassChoice, std::string> choose_classes(const std::vector<std::string>& only,
                                                          const std::vector<std::string>& skip);

}  // namespace mblab::robustness
