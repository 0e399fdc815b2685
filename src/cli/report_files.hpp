#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mblab::cli {

// "-" for a report: standard output.
inline constexpr std::string_view kStandardOutput = "-";

// The report files of a run, checked before any traffic: a run of an hour must not end with
// "cannot write". The check makes no file (an existing one is opened for writing, a missing one
// is tried as the temporary file it will be written through, and removed at once), and the
// reports are written whole when the run ends (conformance::write_text_file), so a refused,
// failed or killed run (`conform ... | head`) leaves no empty report and an earlier report stays
// whole until the new one replaces it. Shared by conform, load and fuzz.
class ReportFiles {
  public:
    // False with `error` naming the option and the path when `path` cannot be written. "-" is
    // standard output, which only one report may take.
    bool check(std::string_view option, const std::string& path, std::string& error);

    // `text` to `path`, or to standard output for "-"; false with `error` when it cannot.
    static bool write(const std::string& path, const std::string& text, std::string& error);
    // Whether a report checked goes to standard output (the console text then goes to stderr).
    bool uses_standard_output() const { return !standard_output_.empty(); }

  private:
    std::vector<std::pair<std::string, std::string>> checked_;  // option, absolute path
    std::string standard_output_;                               // the option that has it
};

// --json, --junit and --html: the text reports of a command that judges a run (conform,
// conform-client, load), declared, checked and sent to standard output the same way.
struct TextReports {
    std::string json;
    std::string junit;
    std::string html;

    // `junit_case`: what one JUnit test case stands for ("case"); `html_page`: what the HTML
    // page shows.
    void add_to(CLI::App& command, std::string_view junit_case, std::string_view html_page);
    bool check(ReportFiles& files, std::string& error) const;
    bool wanted() const { return !json.empty() || !junit.empty() || !html.empty(); }
    // Whether one report goes to standard output (the console report then goes to stderr).
    bool to_stdout() const {
        return json == kStandardOutput || junit == kStandardOutput || html == kStandardOutput;
    }
};

}  // namespace mblab::cli
