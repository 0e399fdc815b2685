#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "conformance/engine.hpp"
#include "conformance/session.hpp"

namespace mblab::conformance {

// The console report: one line per case as it finishes, the evidence under each failure, a
// summary at the end. The progress line of long procedures goes to its own stream (stderr) and
// only when that is a terminal.
class ConsoleReport : public RunListener, public Progress {
  public:
    // `colour`: verdicts in colour (PASS green, FAIL red, N/A and NOT RUN yellow), for a terminal.
    // `width`: the evidence of a failure is cut to lines of this many columns (0: never cut).
    ConsoleReport(std::FILE* out, std::FILE* progress, bool show_progress, bool colour = false,
                  std::size_t width = 0)
        : out_(out),
          progress_(progress),
          show_progress_(show_progress),
          colour_(colour),
          width_(width) {}

    void header(const std::string& target, const Dut& dut, const std::string& note);
    void suite_started(const Suite& suite) override;
    void case_finished(const Suite& suite, const CaseResult& result) override;
    void summary(const RunResult& result);

    void update(std::string_view what, std::size_t done, std::size_t total) override;
    void clear() override;

  private:
    // A suite none of whose cases can run here (suite_inapplicable) is one line; its case lines
    // wait until that is known.
    void flush_suite();
    std::string case_line(const CaseResult& result) const;
    std::string verdict_cell(Verdict verdict) const;

    std::FILE* out_;
    std::FILE* progress_;
    bool show_progress_;
    bool colour_;
    std::size_t width_;
    bool progress_shown_ = false;
    std::size_t id_width_ = 8;
    std::string suite_name_;
    std::size_t suite_cases_ = 0;
    std::vector<CaseResult> held_;  // N/A cases of this suite, all for one reason so far
};

// The summary's guidance: how many N/A cases each missing declaration holds back, most first:
// "registers (4), coils (4), read_only_register (3)". Empty when none does.
std::string undeclared_guidance(const RunResult& result);

}  // namespace mblab::conformance
