#include "cli/conform_reports.hpp"

#include <cstdio>

#include "conformance/reports.hpp"
#include "web/html_report.hpp"

namespace mblab::cli {

namespace conf = mblab::conformance;

bool ConformReports::check(ReportFiles& files, std::string& error) const {
    if (pcap == kStandardOutput) {
        error = "--pcap -: a capture is binary; give it a file (tshark -r FILE reads it)";
        return false;
    }
    return files.check("--json", json, error) && files.check("--junit", junit, error) &&
           files.check("--pcap", pcap, error) && files.check("--html", html, error);
}

bool ConformReports::write(const conf::RunResult& result, const conf::Provenance& provenance,
                           const conf::Capture& capture, client::Framing framing,
                           ReportFiles& files, std::string& error) const {
    if (!json.empty() && !files.write(json, conf::json_report(result, provenance), error))
        return false;
    if (!junit.empty() && !files.write(junit, conf::junit_report(result, provenance), error))
        return false;
    if (!html.empty() && !files.write(html, web::conform_html_report(result, provenance), error))
        return false;
    return pcap.empty() || conf::write_capture(pcap, capture.events(), framing, provenance, error);
}

}  // namespace mblab::cli
