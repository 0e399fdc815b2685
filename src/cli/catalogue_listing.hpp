#pragma once

#include <vector>

#include "conformance/catalogue.hpp"

// `mblab conform --list`: the cases of each suite, then the documents their sources cite.
namespace mblab::cli {

void print_catalogue(const std::vector<conformance::Suite>& suites);

}  // namespace mblab::cli
