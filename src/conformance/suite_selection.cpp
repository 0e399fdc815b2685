#include "conformance/suite_selection.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <optional>

#include "conformance/catalogue_paths.hpp"
#include "support/suggestion.hpp"

namespace mblab::conformance {

namespace {

// A suite given as a file, or by the name of a shipped one ([suite] name or file stem).
std::optional<std::string> find_suite(const std::string& wanted,
                                      const std::vector<std::string>& shipped, std::string& error) {
    namespace fs = std::filesystem;
    std::error_code ignored;
    if (wanted.ends_with(".toml") || wanted.find('/') != std::string::npos ||
        fs::is_regular_file(wanted, ignored)) {
        if (!fs::is_regular_file(wanted, ignored)) {
            error = fmt::format("suite file {} does not exist", wanted);
            return std::nullopt;
        }
        return wanted;
    }
    std::string names;
    std::vector<std::string> candidates;
    for (const auto& file : shipped) {
        if (fs::path(file).stem() == wanted) return file;
        auto suite = load_suite_file(file);
        if (suite && suite->name == wanted) return file;
        names += (names.empty() ? "" : ", ") + fs::path(file).stem().string();
        candidates.push_back(fs::path(file).stem().string());
        if (suite) candidates.push_back(suite->name);
    }
    const auto near = support::nearest(wanted, candidates);
    error = fmt::format("no suite named '{}'{} (shipped suites: {})", wanted,
                        near ? fmt::format("; did you mean '{}'?", *near) : std::string(), names);
    return std::nullopt;
}

}  // namespace

bool load_suites(const std::string& catalogue, const std::vector<std::string>& wanted_suites,
                 std::vector<Suite>& suites, std::string& error) {
    const std::string dir = catalogue.empty() ? catalogue_dir().string() : catalogue;
    const auto shipped = shipped_suite_files(dir);
    std::vector<std::string> files;
    if (wanted_suites.empty()) {
        files = shipped;
        if (files.empty()) {
            error = fmt::format("no suites in {} (use --catalogue DIR or --suite FILE)", dir);
            return false;
        }
    }
    for (const auto& wanted : wanted_suites) {
        auto file = find_suite(wanted, shipped, error);
        if (!file) return false;
        files.push_back(*file);
    }
    for (const auto& file : files) {
        auto suite = load_suite_file(file);
        if (!suite) {
            error = suite.error();
            return false;
        }
        suites.push_back(std::move(suite.value()));
    }
    return true;
}

// A case id pattern: `*` stands for any run of characters, `?` for any one; the rest is literal.
bool glob_match(std::string_view pattern, std::string_view text) {
    std::size_t p = 0;
    std::size_t t = 0;
    std::size_t star = std::string_view::npos;  // the last `*` seen, to retry from on a mismatch
    std::size_t star_text = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            star_text = t;
        } else if (star != std::string_view::npos) {
            p = star + 1;
            t = ++star_text;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*')
        ++p;
    return p == pattern.size();
}

// Keeps the cases that match a --case pattern, with the earlier cases they depend on: a chosen
// case's dependencies decide whether it can run at all, so rerunning it alone would otherwise
// judge it without them. Suites with no case left are dropped. Every pattern must match a case,
// or the user's typo would silently run nothing of what was meant.
bool select_cases(const std::vector<std::string>& patterns, std::vector<Suite>& suites,
                  std::string& error) {
    if (patterns.empty()) return true;
    std::string names;
    for (const auto& suite : suites)
        names += (names.empty() ? "" : ", ") + suite.name;
    std::vector<bool> used(patterns.size(), false);
    std::vector<Suite> chosen;
    for (auto& suite : suites) {
        std::vector<bool> keep(suite.cases.size(), false);
        for (std::size_t i = 0; i < suite.cases.size(); ++i) {
            for (std::size_t n = 0; n < patterns.size(); ++n) {
                if (glob_match(patterns[n], suite.cases[i].id)) keep[i] = used[n] = true;
            }
        }
        // Dependencies are earlier cases, so one pass from the end takes them transitively.
        for (std::size_t i = suite.cases.size(); i-- > 0;) {
            if (!keep[i]) continue;
            for (const auto& dependency : suite.cases[i].depends_on) {
                for (std::size_t j = 0; j < i; ++j) {
                    if (suite.cases[j].id == dependency) keep[j] = true;
                }
            }
        }
        std::vector<Case> cases;
        for (std::size_t i = 0; i < suite.cases.size(); ++i) {
            if (keep[i]) cases.push_back(std::move(suite.cases[i]));
        }
        if (cases.empty()) continue;
        suite.cases = std::move(cases);
        chosen.push_back(std::move(suite));
    }
    for (std::size_t n = 0; n < patterns.size(); ++n) {
        if (used[n]) continue;
        error = fmt::format(
            "--case '{}' matches no case of the selected suites ({}); conform --list shows the "
            "case ids",
            patterns[n], names);
        return false;
    }
    suites = std::move(chosen);
    return true;
}

}  // namespace mblab::conformance
