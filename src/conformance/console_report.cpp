#include "conformance/console_report.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/evidence_text.hpp"

namespace mblab::conformance {

void ConsoleReport::header(const std::string& target, const Dut& dut, const std::string& note) {
    fmt::print(out_, "mblab conform {}{}\n", target, note.empty() ? "" : " (" + note + ")");
    fmt::print(out_, "DUT: {} (declared by {})\n", describe_dut(dut), dut.declared_by);
}

void ConsoleReport::suite_started(const Suite& suite) {
    id_width_ = 0;
    for (const auto& c : suite.cases)
        id_width_ = std::max(id_width_, c.id.size());
    fmt::print(out_, "\n{}{}\n", suite.name, suite.title.empty() ? "" : ": " + suite.title);
    std::fflush(out_);
}

void ConsoleReport::case_finished(const Suite&, const CaseResult& result) {
    clear();
    const auto& outcome = result.outcome;
    const auto label = verdict_label(outcome.verdict);
    std::string shown = fmt::format("{:<8}", label);
    if (colour_) {
        const char* colour = outcome.verdict == Verdict::Pass   ? "\x1b[32m"
                             : outcome.verdict == Verdict::Fail ? "\x1b[31m"
                                                                : "\x1b[33m";
        // Only the word is coloured, so the columns stay where they are.
        shown = fmt::format("{}{}\x1b[0m{}", colour, label, shown.substr(label.size()));
    }
    std::string line = fmt::format("  {} {:<{}}  {}", shown, result.id, id_width_, result.title);
    if (!outcome.reason.empty()) line += fmt::format("  ({})", outcome.reason);
    fmt::print(out_, "{}\n", line);
    const std::string indent(11, ' ');
    for (const auto& exchange : outcome.evidence) {
        for (const auto& text : evidence_lines(exchange))
            fmt::print(out_, "{}{}\n", indent, text);
    }
    std::fflush(out_);
}

void ConsoleReport::summary(const RunResult& result) {
    const Counts counts = result.counts();
    fmt::print(out_,
               "\nSummary: {} passed, {} failed, {} N/A, {} not run ({} cases) in {}, {} "
               "requests\n",
               counts.passed, counts.failed, counts.not_applicable, counts.not_run, counts.total(),
               format_duration(result.elapsed), result.requests);
    if (result.interrupted) {
        std::size_t left = 0;
        for (const auto& suite : result.suites) {
            for (const auto& c : suite.cases)
                left += c.interrupted ? 1 : 0;
        }
        fmt::print(out_,
                   "Interrupted: {} of {} cases run; the reports mark the other {} NOT RUN "
                   "(interrupted)\n",
                   counts.total() - left, counts.total(), left);
    }
    std::fflush(out_);
}

void ConsoleReport::update(std::string_view what, std::size_t done, std::size_t total) {
    if (!show_progress_) return;
    // Redrawing every answer would cost more than the answers; a few dozen steps suffice.
    const std::size_t step = std::max<std::size_t>(1, total / 50);
    if (done != total && done % step != 0) return;
    fmt::print(progress_, "\r  {}: {}/{} requests\x1b[K", what, done, total);
    std::fflush(progress_);
    progress_shown_ = true;
}

void ConsoleReport::clear() {
    if (!progress_shown_) return;
    fmt::print(progress_, "\r\x1b[K");
    std::fflush(progress_);
    progress_shown_ = false;
}

}  // namespace mblab::conformance
