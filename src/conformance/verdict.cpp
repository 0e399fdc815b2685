#include "conformance/verdict.hpp"

namespace mblab::conformance {

std::string_view verdict_label(Verdict verdict) {
    switch (verdict) {
        case Verdict::Pass:
            return "PASS";
        case Verdict::Fail:
            return "FAIL";
        case Verdict::NotApplicable:
            return "N/A";
        case Verdict::NotRun:
            return "NOT RUN";
    }
    return "?";
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

}  // namespace mblab::conformance
