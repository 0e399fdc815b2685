// Which suites and cases a run takes (conformance/suite_selection.hpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "conformance/suite_selection.hpp"

namespace mblab::conformance {
namespace {

TEST(GlobMatch, StarAndQuestionMarkOverCaseIds) {
    struct Row {
        const char* pattern;
        const char* id;
        bool matches;
    };
    // clang-format off
    const Row rows[] = {
        {"7.*", "7.10.1", true},   {"7.?.1", "7.3.1", true},     {"7.?.1", "7.10.1", false},
        {"*", "", true},           {"a*b*c", "aXbYbZc", true},  {"a*b", "aXbY", false},
        {"9.1.1", "9.1.1", true},  {"9.1.1", "9.1.10", false},
    };
    // clang-format on
    for (const auto& row : rows)
        EXPECT_EQ(glob_match(row.pattern, row.id), row.matches) << row.pattern << " ~ " << row.id;
}

Suite suite_of(std::vector<std::pair<std::string, std::vector<std::string>>> cases) {
    Suite suite;
    suite.name = "s";
    for (auto& [id, depends] : cases) {
        Case c;
        c.id = id;
        c.depends_on = depends;
        suite.cases.push_back(std::move(c));
    }
    return suite;
}

TEST(SelectCases, KeepsTheMatchesAndWhatTheyDependOnTransitively) {
    std::vector<Suite> suites{suite_of({{"a", {}}, {"b", {"a"}}, {"c", {"b"}}, {"d", {}}})};
    std::string error;
    ASSERT_TRUE(select_cases({"c"}, suites, error)) << error;
    ASSERT_EQ(suites.size(), 1U);
    std::vector<std::string> ids;
    for (const auto& c : suites[0].cases)
        ids.push_back(c.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"a", "b", "c"}));
}

TEST(SelectCases, APatternThatMatchesNothingIsAnError) {
    std::vector<Suite> suites{suite_of({{"a", {}}})};
    std::string error;
    EXPECT_FALSE(select_cases({"a", "zz*"}, suites, error));
    EXPECT_EQ(error,
              "--case 'zz*' matches no case of the selected suites (s); conform --list shows the "
              "case ids");
}

TEST(LoadSuites, AMistypedShippedSuiteGetsTheNearestName) {
    std::vector<Suite> suites;
    std::string error;
    EXPECT_FALSE(
        load_suites(std::string(MBLAB_SOURCE_DIR) + "/catalogue", {"polcy-2.1"}, suites, error));
    EXPECT_NE(error.find("did you mean 'policy-2.1'?"), std::string::npos) << error;
}

}  // namespace
}  // namespace mblab::conformance
