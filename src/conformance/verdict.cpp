#include "conformance/verdict.hpp"

#include <fmt/core.h>

#include "support/name_table.hpp"

namespace mblab::conformance {

std::string_view verdict_label(Verdict verdict) {
    static constexpr Named<Verdict> kLabels[] = {{Verdict::Pass, "PASS"},
                                                 {Verdict::Fail, "FAIL"},
                                                 {Verdict::NotApplicable, "N/A"},
                                                 {Verdict::NotRun, "NOT RUN"}};
    return name_of(kLabels, verdict, "?");
}

void Counts::add(Verdict verdict) {
    std::size_t* const slots[] = {&passed, &failed, &not_applicable, &not_run};
    ++*slots[static_cast<std::size_t>(verdict)];
}

Counts& Counts::operator+=(const Counts& other) {
    passed += other.passed;
    failed += other.failed;
    not_applicable += other.not_applicable;
    not_run += other.not_run;
    return *this;
}

Counts count(const SuiteResult& suite) {
    Counts counts;
    for (const auto& c : suite.cases)
        counts.add(c.outcome.verdict);
    return counts;
}

Counts RunResult::counts() const {
    Counts total;
    for (const auto& suite : suites)
        total += count(suite);
    return total;
}

std::optional<Inapplicable> suite_inapplicable(std::string_view suite_name,
                                               std::span<const CaseResult> cases) {
    if (cases.size() < 2) return std::nullopt;
    const std::string& reason = cases.front().outcome.reason;
    for (const auto& c : cases) {
        if (c.outcome.verdict != Verdict::NotApplicable || c.interrupted ||
            c.outcome.reason != reason) {
            return std::nullopt;
        }
    }
    return Inapplicable{fmt::format("all {} cases of {}", cases.size(), suite_name), reason};
}

}  // namespace mblab::conformance
