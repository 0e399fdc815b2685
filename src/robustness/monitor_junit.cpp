#include "robustness/monitor_junit.hpp"

#include <fmt/core.h>

#include "conformance/reports.hpp"
#include "robustness/ladder_report.hpp"

namespace mblab::robustness {

namespace {

// The cases that lost cycles, a line each after the requirement of the phase they ran in.
std::string during_text(const MonitorJudgement& judged, const MonitorPhase& phase) {
    std::string out;
    if (phase.name != kCasesPhase) return out;
    for (const auto& d : judged.missed_during) {
        out += '\n';
        out += missed_during_text(d);
    }
    return out;
}

std::string missed_words(const PhaseJudgement& p) {
    return fmt::format("{} of {} cycles missed ({:.1f}%)", p.missed, p.cycles, p.missed_percent);
}

// Whether `phase` is a rung of the ladder: a rung is judged in its storm's case, so that one
// loss is one failure.
bool is_rung(const std::string& phase, const std::vector<LadderRung>& rungs) {
    for (const auto& rung : rungs) {
        if (phase == storm_phase_name(rung.kind, rung.rate)) return true;
    }
    return false;
}

// A test case per storm: failed where a rung lost the monitor, with that rung's missed cycles;
// skipped where it did not run.
std::string storm_cases(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                        const std::vector<StormNotRun>& not_run, JunitSuite& out) {
    using conformance::xml_escape;
    std::string cases;
    for (const auto& s : storm_summaries(judged, rungs)) {
        ++out.tests;
        const auto words = fmt::format("{} [{}]", summary_words(s), storm_tag(s.kind));
        cases += fmt::format("    <testcase classname=\"monitor.ladder\" name=\"{}\" time=\"0\">",
                             storm_key(s.kind));
        if (s.lost_at) {
            ++out.failures;
            std::string detail;
            const auto rung = storm_phase_name(s.kind, *s.lost_at);
            for (const auto& p : judged.phases) {
                if (p.phase.name == rung)
                    detail = rung + ": " + missed_words(p) + "\n" + p.phase.requirement;
            }
            cases += fmt::format(
                "\n      <failure message=\"{}\" type=\"monitor lost\">{}</failure>\n    ",
                xml_escape(words), xml_escape(detail));
        } else {
            cases += fmt::format("\n      <system-out>{}</system-out>\n    ", xml_escape(words));
        }
        cases += "</testcase>\n";
    }
    for (const auto& n : not_run) {
        ++out.tests;
        ++out.skipped;
        cases += fmt::format(
            "    <testcase classname=\"monitor.ladder\" name=\"{}\" time=\"0\">\n      "
            "<skipped message=\"{}\"/>\n    </testcase>\n",
            storm_key(n.kind), xml_escape("not run: " + n.reason));
    }
    return cases;
}

}  // namespace

JunitSuite monitor_junit_suite(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                               const std::vector<StormNotRun>& not_run) {
    using conformance::xml_escape;
    JunitSuite out;
    std::string cases;
    for (const auto& p : judged.phases) {
        if (is_rung(p.phase.name, rungs)) continue;
        const double seconds =
            static_cast<double>(
                std::chrono::duration_cast<std::chrono::milliseconds>(p.phase.end - p.phase.begin)
                    .count()) /
            1000.0;
        ++out.tests;
        cases += fmt::format("    <testcase classname=\"monitor\" name=\"{}\" time=\"{:.3f}\">",
                             xml_escape(p.phase.name), seconds > 0 ? seconds : 0.0);
        if (!p.held) {
            ++out.failures;
            cases += fmt::format(
                "\n      <failure message=\"{}\" type=\"monitor lost\">{}</failure>\n    ",
                xml_escape(missed_words(p)),
                xml_escape(p.phase.requirement + during_text(judged, p.phase)));
        }
        cases += "</testcase>\n";
    }
    cases += storm_cases(judged, rungs, not_run, out);
    ++out.tests;
    cases += "    <testcase classname=\"monitor\" name=\"verdict\" time=\"0\">";
    if (judged.verdict != MonitorVerdict::Pass) {
        ++out.failures;
        cases +=
            fmt::format("\n      <failure message=\"{}\" type=\"{}\"/>\n    ",
                        xml_escape(fmt::format("{}: {}", verdict_name(judged.verdict), judged.why)),
                        verdict_name(judged.verdict));
    }
    cases += "</testcase>\n";
    out.xml = fmt::format(
        "  <testsuite name=\"essential-function monitor\" tests=\"{}\" failures=\"{}\" "
        "errors=\"0\" skipped=\"{}\" time=\"0\">\n{}  </testsuite>\n",
        out.tests, out.failures, out.skipped, cases);
    return out;
}

}  // namespace mblab::robustness
