#include "cli/conform_reports.hpp"

#include <cstdio>

#include "conformance/reports.hpp"
#include "web/html_report.hpp"

namespace mblab::cli {

namespace conf = mblab::conformance;

namespace {

constexpr const char* kStdout = "-";

// A text report to its file, or to standard output for `-`.
bool emit(const std::string& path, const std::string& text, ReportFiles& files,
          std::string& error) {
    if (path == kStdout) {
        std::fwrite(text.data(), 1, text.size(), stdout);
        std::fflush(stdout);
        return true;
    }
    if (!conf::write_text_file(path, text, error)) return false;
    files.written(path);
    return true;
}

}  // namespace

bool ConformReports::check(ReportFiles& files, std::string& error) const {
    if ((json == kStdout) + (junit == kStdout) + (html == kStdout) > 1) {
        error = "only one report can go to standard output (-)";
        return false;
    }
    if (pcap == kStdout) {
        error = "--pcap -: a capture is binary; give it a file (tshark -r FILE reads it)";
        return false;
    }
    const auto file = [&](const char* option, const std::string& path) {
        return path == kStdout || files.check(option, path, error);
    };
    return file("--json", json) && file("--junit", junit) && files.check("--pcap", pcap, error) &&
           file("--html", html);
}

bool ConformReports::write(const conf::RunResult& result, const conf::Provenance& provenance,
                           const conf::Capture& capture, client::Framing framing,
                           ReportFiles& files, std::string& error) const {
    if (!json.empty() && !emit(json, conf::json_report(result, provenance), files, error))
        return false;
    if (!junit.empty() && !emit(junit, conf::junit_report(result, provenance), files, error))
        return false;
    if (!html.empty() && !emit(html, web::conform_html_report(result, provenance), files, error))
        return false;
    if (!pcap.empty()) {
        if (!conf::write_capture(pcap, capture.events(), framing, provenance, error)) return false;
        files.written(pcap);
    }
    return true;
}

}  // namespace mblab::cli
