#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

// Did-you-mean for whatever a user names: commands, options, suites, profiles.
namespace mblab::support {

// The name in `names` nearest to `word`, when near enough to be what was meant: at most two
// edits (one for words of four letters or fewer), a swap of neighbours counting as one.
std::optional<std::string> nearest(std::string_view word, const std::vector<std::string>& names);

}  // namespace mblab::support
