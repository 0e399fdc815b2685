#include "cli/conform_reports.hpp"

#include "conformance/reports.hpp"
#include "web/html_report.hpp"

namespace mblab::cli {

namespace conf = mblab::conformance;

bool ConformReports::check(ReportFiles& files, std::string& error) const {
    return files.check("--json", json, error) && files.check("--junit", junit, error) &&
           files.check("--pcap", pcap, error) && files.check("--html", html, error);
}

bool ConformReports::write(const conf::RunResult& result, const conf::Provenance& provenance,
                           const conf::Capture& capture, ReportFiles& files,
                           std::string& error) const {
    if (!json.empty()) {
        if (!conf::write_text_file(json, conf::json_report(result, provenance), error))
            return false;
        files.written(json);
    }
    if (!junit.empty()) {
        if (!conf::write_text_file(junit, conf::junit_report(result, provenance), error))
            return false;
        files.written(junit);
    }
    if (!html.empty()) {
        if (!conf::write_text_file(html, web::conform_html_report(result, provenance), error))
            return false;
        files.written(html);
    }
    if (!pcap.empty()) {
        if (!conf::write_pcap(pcap, capture.events(), provenance, error)) return false;
        files.written(pcap);
    }
    return true;
}

}  // namespace mblab::cli
