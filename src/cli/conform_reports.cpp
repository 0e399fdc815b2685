#include "cli/conform_reports.hpp"

#include <cstdio>

#include "conformance/reports.hpp"
#include "web/html_report.hpp"

namespace mblab::cli {

namespace conf = mblab::conformance;

void ConformReports::add_to(CLI::App& command, std::string_view item) {
    const std::string each(item);
    TextReports::add_to(command, each,
                        "each " + each + "'s verdict and citation, and what the wire carried");
    command.add_option("--pcap", pcap,
                       "write what the wire carried to FILE as pcapng, each packet's comment its " +
                           each +
                           "'s id; a line's frames on link type USER0 (RTU) or USER1 (ASCII). "
                           "Every report file is checked before any traffic");
}

bool ConformReports::check(ReportFiles& files, std::string& error) const {
    if (pcap == kStandardOutput) {
        error = "--pcap -: a capture is binary; give it a file (tshark -r FILE reads it)";
        return false;
    }
    return TextReports::check(files, error) && files.check("--pcap", pcap, error);
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
