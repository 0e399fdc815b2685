#include "cli/suite_options.hpp"

#include "conformance/suite_selection.hpp"

namespace mblab::cli {

void SuiteOptions::add_to(CLI::App& command, std::string_view suite_help) {
    command.add_option("--suite", suites, std::string(suite_help));
    command.add_option("--case", cases,
                       "run only the cases whose id matches, e.g. 7.5.1 or '7.5.*' (* any text, ? "
                       "any one character), with the cases they depend on; repeatable");
    command.add_option("--catalogue", catalogue, "directory of the shipped suites");
}

bool SuiteOptions::choose(const std::vector<std::string>& default_suites,
                          std::vector<conformance::Suite>& chosen, std::string& error) const {
    return conformance::load_suites(catalogue, suites.empty() ? default_suites : suites, chosen,
                                    error) &&
           conformance::select_cases(cases, chosen, error);
}

}  // namespace mblab::cli
