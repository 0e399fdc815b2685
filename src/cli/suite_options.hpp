#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "conformance/catalogue.hpp"

// --suite, --case and --catalogue: the cases of the catalogue a command runs (conform, and load,
// which loops their request/response exchanges). Both choose them the same way: suites by file or
// shipped name (conformance::load_suites), cases by id pattern with the cases they depend on
// (conformance::select_cases).
namespace mblab::cli {

struct SuiteOptions {
    std::vector<std::string> suites;
    std::vector<std::string> cases;
    std::string catalogue;

    // `suite_help`: what --suite picks, and its default.
    void add_to(CLI::App& command, std::string_view suite_help);
    // The chosen suites, `default_suites` (every shipped suite when empty) when no --suite was
    // given. False with a one-line `error` for a suite not found or a pattern matching no case.
    bool choose(const std::vector<std::string>& default_suites,
                std::vector<conformance::Suite>& chosen, std::string& error) const;
};

}  // namespace mblab::cli
