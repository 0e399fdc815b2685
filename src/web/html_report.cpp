#include "web/html_report.hpp"

#include <fmt/core.h>

#include "conformance/evidence_text.hpp"
#include "web/case_table.hpp"
#include "web/page.hpp"

namespace mblab::web {

namespace conf = mblab::conformance;

std::string outcome_banner(const conf::RunResult& result) {
    const conf::Counts counts = result.counts();
    if (result.interrupted) {
        std::size_t left = 0;
        for (const auto& suite : result.suites) {
            for (const auto& c : suite.cases)
                left += c.interrupted ? 1 : 0;
        }
        return fmt::format(
            "<p class=\"banner INCOMPLETE\" id=\"outcome\">INTERRUPTED: the run was interrupted "
            "after {} of {} cases; the other {} are NOT RUN (interrupted)</p>\n",
            counts.total() - left, counts.total(), left);
    }
    if (result.all_passed())
        return "<p class=\"banner PASS\" id=\"outcome\">PASSED: no case failed</p>\n";
    return fmt::format(
        "<p class=\"banner FAIL\" id=\"outcome\">FAILED: {} of {} cases failed</p>\n",
        counts.failed, counts.total());
}

std::string summary_table(const conf::RunResult& result) {
    const conf::Counts counts = result.counts();
    return fmt::format(
        "<table id=\"summary\">\n<tr><th class=\"PASS\">passed</th><th class=\"FAIL\">failed</th>"
        "<th class=\"NA\">N/A</th><th class=\"NOTRUN\">not run</th><th>cases</th><th>time</th>"
        "<th>requests</th></tr>\n<tr><td class=\"number\">{}</td><td class=\"number\">{}</td>"
        "<td class=\"number\">{}</td><td class=\"number\">{}</td><td class=\"number\">{}</td>"
        "<td class=\"number\">{}</td><td class=\"number\">{}</td></tr>\n</table>\n",
        counts.passed, counts.failed, counts.not_applicable, counts.not_run, counts.total(),
        html_escape(conf::format_duration(result.elapsed)), result.requests);
}

namespace {

std::string declarations_table(const conf::Provenance& provenance) {
    std::string out =
        "<table id=\"declarations\">\n<tr><th>key</th><th>value</th><th>declared by</th></tr>\n";
    for (const auto& declaration : provenance.declarations) {
        out += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                           html_escape(declaration.key), html_escape(conf::value_text(declaration)),
                           html_escape(declaration.source));
    }
    return out + "</table>\n";
}

std::string identity_table(const conf::DeviceIdentity& device) {
    std::string out = "<table id=\"identity\">\n";
    if (device.answered) {
        out += field_row("vendor name (object 00)", device.vendor_name);
        out += field_row("product code (object 01)", device.product_code);
        out += field_row("revision (object 02)", device.revision);
    } else {
        out += field_row("not answered", device.reason);
    }
    return out + "</table>\n";
}

}  // namespace

std::string provenance_table(const conf::Provenance& provenance) {
    return "<table id=\"provenance\">\n" + field_row("mblab version", provenance.version) +
           field_row("git commit", provenance.commit) + field_row("started", provenance.started) +
           field_row("finished", provenance.finished) +
           field_row("command line", conf::shell_words(provenance.command_line)) + "</table>\n";
}

std::string conform_html_report(const conf::RunResult& result, const conf::Provenance& provenance) {
    std::string body = fmt::format("<h1>mblab conform {}</h1>\n", html_escape(result.target));
    body += outcome_banner(result);
    body += summary_table(result);
    body += fmt::format("<h2>Device under test</h2>\n<p>{} (declared by {})</p>\n",
                        html_escape(conf::describe_dut(result.dut)),
                        html_escape(provenance.declared_by));
    body += declarations_table(provenance);
    body += "<h2>Device identification (FC 2B / 0E)</h2>\n" + identity_table(provenance.device);
    body += "<h2>Provenance</h2>\n" + provenance_table(provenance);
    body += "<h2>Cases</h2>\n" + case_filters();
    for (const auto& suite : result.suites) {
        body += fmt::format("<section class=\"suite\">\n<h2>{}{} <small>({})</small></h2>\n",
                            html_escape(suite.name),
                            suite.title.empty() ? "" : ": " + html_escape(suite.title),
                            html_escape(suite.file));
        body += case_table(suite) + "</section>\n";
    }
    return html_page("mblab conform " + result.target, body);
}

}  // namespace mblab::web
