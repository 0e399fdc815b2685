#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "conformance/catalogue.hpp"

// Which suites and cases a run takes, from what the user named: suites by file or by the name of
// a shipped one, cases by id patterns with the earlier cases they depend on.
namespace mblab::conformance {

// The suites named in `wanted` (files, or shipped suites by [suite] name or file stem; every
// shipped suite when empty) from `catalogue` (the shipped catalogue when empty). False with a
// one-line `error`, a near name suggested, when one cannot be found or read.
bool load_suites(const std::string& catalogue, const std::vector<std::string>& wanted,
                 std::vector<Suite>& suites, std::string& error);

// A case id pattern: `*` stands for any run of characters, `?` for any one; the rest is literal.
bool glob_match(std::string_view pattern, std::string_view text);

// Keeps the cases that match a pattern, with the earlier cases they depend on; suites with no
// case left are dropped. False with `error` when a pattern matches no case.
bool select_cases(const std::vector<std::string>& patterns, std::vector<Suite>& suites,
                  std::string& error);

}  // namespace mblab::conformance
