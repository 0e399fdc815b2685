#include "cli/profile_lookup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <system_error>
#include <vector>

#include "device/profile_paths.hpp"
#include "support/suggestion.hpp"

namespace mblab::cli {

std::optional<std::filesystem::path> find_profile(const std::string& wanted, std::string& error) {
    namespace fs = std::filesystem;
    std::error_code ignored;
    if (fs::is_regular_file(wanted, ignored)) return fs::path(wanted);
    const auto dir = device::profiles_dir();
    const auto shipped = dir / (wanted + ".toml");
    if (wanted.find('/') == std::string::npos && fs::is_regular_file(shipped, ignored)) {
        return shipped;
    }
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir, ignored)) {
        if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    const auto near = support::nearest(wanted, names);
    error = fmt::format("no profile file or shipped profile named '{}'{} (shipped: {})", wanted,
                        near ? fmt::format("; did you mean '{}'?", *near) : std::string(),
                        names.empty() ? "none found" : fmt::format("{}", fmt::join(names, ", ")));
    return std::nullopt;
}

}  // namespace mblab::cli
