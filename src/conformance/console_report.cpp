#include "conformance/console_report.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "conformance/evidence_text.hpp"

namespace mblab::conformance {

void ConsoleReport::header(const std::string& target, const Dut& dut, const std::string& note) {
    fmt::print(out_, "mblab conform {}{}\n", target, note.empty() ? "" : " (" + note + ")");
    fmt::print(out_, "DUT: {} (declared by {})\n", describe_dut(dut), dut.declared_by);
}

void ConsoleReport::suite_started(const Suite& suite) {
    flush_suite();
    id_width_ = 0;
    for (const auto& c : suite.cases)
        id_width_ = std::max(id_width_, c.id.size());
    suite_name_ = suite.name;
    suite_cases_ = suite.cases.size();
    fmt::print(out_, "\n{}{}\n", suite.name, suite.title.empty() ? "" : ": " + suite.title);
    std::fflush(out_);
}

std::string ConsoleReport::verdict_cell(Verdict verdict) const {
    const auto label = verdict_label(verdict);
    std::string shown = fmt::format("{:<8}", label);
    if (!colour_) return shown;
    const char* colour = verdict == Verdict::Pass   ? "\x1b[32m"
                         : verdict == Verdict::Fail ? "\x1b[31m"
                                                    : "\x1b[33m";
    // Only the word is coloured, so the columns stay where they are.
    return fmt::format("{}{}\x1b[0m{}", colour, label, shown.substr(label.size()));
}

std::string ConsoleReport::case_line(const CaseResult& result) const {
    std::string line = fmt::format("  {} {:<{}}  {}", verdict_cell(result.outcome.verdict),
                                   result.id, id_width_, result.title);
    if (!result.outcome.reason.empty()) line += fmt::format("  ({})", result.outcome.reason);
    return line;
}

void ConsoleReport::case_finished(const Suite&, const CaseResult& result) {
    clear();
    const auto& outcome = result.outcome;
    const bool same_na = outcome.verdict == Verdict::NotApplicable &&
                         (held_.empty() || held_.front().outcome.reason == outcome.reason);
    if (same_na && held_.size() + 1 < suite_cases_) {
        held_.push_back(result);
        return;
    }
    if (same_na) {
        held_.push_back(result);
        if (auto inapplicable = suite_inapplicable(suite_name_, held_)) {
            held_.clear();
            fmt::print(out_, "  {} {}  ({})\n", verdict_cell(outcome.verdict), inapplicable->title,
                       inapplicable->reason);
            std::fflush(out_);
            return;
        }
        held_.pop_back();
    }
    flush_suite();
    fmt::print(out_, "{}\n", case_line(result));
    constexpr std::size_t kIndent = 11;
    const std::string indent(kIndent, ' ');
    for (const auto& exchange : outcome.evidence) {
        const auto lines = evidence_lines(exchange);
        for (const auto& text : wrap_evidence(lines, width_ > kIndent ? width_ - kIndent : 0))
            fmt::print(out_, "{}{}\n", indent, text);
    }
    std::fflush(out_);
}

void ConsoleReport::flush_suite() {
    for (const auto& held : held_)
        fmt::print(out_, "{}\n", case_line(held));
    held_.clear();
    std::fflush(out_);
}

void ConsoleReport::summary(const RunResult& result) {
    flush_suite();
    const Counts counts = result.counts();
    fmt::print(out_,
               "\nSummary: {} passed, {} failed, {} N/A, {} not run ({} cases) in {}, {} "
               "requests\n",
               counts.passed, counts.failed, counts.not_applicable, counts.not_run, counts.total(),
               format_duration(result.elapsed), result.requests);
    if (const auto guidance = undeclared_guidance(result); !guidance.empty()) {
        fmt::print(out_,
                   "N/A for want of a declaration, cases per DUT key: {}; declare them in a "
                   "--dut file (docs/catalogue.md) to run those cases\n",
                   guidance);
    }
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

std::string undeclared_guidance(const RunResult& result) {
    std::map<std::string, std::size_t> held_back;
    for (const auto& suite : result.suites) {
        for (const auto& c : suite.cases) {
            if (c.outcome.verdict == Verdict::NotApplicable && !c.outcome.undeclared.empty())
                ++held_back[c.outcome.undeclared];
        }
    }
    std::vector<std::pair<std::string, std::size_t>> keys(held_back.begin(), held_back.end());
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    std::string text;
    for (const auto& [key, count] : keys)
        text += fmt::format("{}{} ({})", text.empty() ? "" : ", ", key, count);
    return text;
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
