#include "conformance/verdict.hpp"

namespace mblab::conformance {

std::string_view verdict_label(Verdict verdict) {
    switch (verdict) {
        case Verdict::Pass: return "PASS";
        case Verdict::Fail: return "FAIL";
        case Verdict::NotApplicable: return "N/A";
        case Verdict::NotRun: return "NOT RUN";
    }
    return "?";
}

Counts count(const SuiteResult& suite) {
    Counts counts;
    for (const auto& c : suite.cases) {
        switch (c.outcome.verdict) {
            case Verdict::Pass: ++counts.passed; break;
            case Verdict::Fail: ++counts.failed; break;
            case Verdict::NotApplicable: ++counts.not_applicable; break;
            case Verdict::NotRun: ++counts.not_run; break;
        }
    }
    return counts;
}

Counts RunResult::counts() const {
    Counts total;
    for (const auto& suite : suites) {
        Counts one = count(suite);
        total.passed += one.passed;
        total.failed += one.failed;
        total.not_applicable += one.not_applicable;
        total.not_run += one.not_run;
    }
    return total;
}

}  // namespace mblab::conformance
