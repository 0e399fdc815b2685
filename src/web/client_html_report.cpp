#include "web/client_html_report.hpp"

#include <fmt/core.h>

#include "conformance/evidence_text.hpp"
#include "web/case_table.hpp"
#include "web/html_report.hpp"
#include "web/page.hpp"

namespace mblab::web {

namespace {

namespace conf = mblab::conformance;

std::string declarations_table(const ClientUnderTest& client, const std::string& declared_by) {
    const auto& d = client.declared;
    std::string out = "<table id=\"client\">\n";
    out += field_row("examiner", client.examiner);
    out +=
        field_row("command", client.command.empty() ? "none: --attach, the client polls by itself"
                                                    : conf::shell_words(client.command));
    if (!client.pki.empty()) out += field_row("PKI", client.pki);
    out += field_row("unit", std::to_string(d.unit));
    out += field_row("registers", fmt::format("{}..{}", d.address, d.address + d.count - 1));
    out += field_row("timeout", d.timeout ? fmt::format("{} ms", d.timeout->count())
                                          : std::string("undeclared"));
    out += field_row("retries", d.retries ? std::to_string(*d.retries) : "undeclared");
    out += field_row("pipelining", d.pipelining ? "yes" : "no");
    out += field_row("broadcast", d.broadcast ? "yes" : "no");
    out += field_row("errors signalled by", d.error_pattern.empty()
                                                ? std::string("a non-zero exit status")
                                                : "output matching /" + d.error_pattern + "/");
    out += field_row("values read by", "/" + d.value_pattern + "/");
    out += field_row("declared by", declared_by);
    return out + "</table>\n";
}

// The wire of one scenario: open for a failure, folded away otherwise.
std::string wire_html(const conf::CaseResult& c, const conf::ClientTranscripts& transcripts) {
    const auto found = transcripts.find(c.id);
    if (found == transcripts.end() || found->second.empty()) return "";
    std::string out = fmt::format(
        "<details class=\"wire\"{}><summary>what the wire carried ({} frames)</summary>"
        "<pre class=\"evidence\">",
        c.outcome.verdict == conf::Verdict::Fail ? " open" : "", found->second.size());
    for (const auto& line : found->second) {
        const auto bytes = html_escape(conf::compact_hex(line.bytes));
        out += fmt::format("{:>6} ms  #{}  {}  {}{}\n", line.at.count(), line.connection,
                           line.from_client ? "client  " : "examiner",
                           line.decoy ? "<mark class=\"diff\">" + bytes + "</mark>" : bytes,
                           line.decoy ? "  (decoy)" : "");
    }
    return out + "</pre></details>\n";
}

}  // namespace

std::string conform_client_html_report(const conf::RunResult& result,
                                       const conf::Provenance& provenance,
                                       const ClientUnderTest& client,
                                       const conf::ClientTranscripts& transcripts) {
    std::string body =
        fmt::format("<h1>mblab conform-client {}</h1>\n", html_escape(client.examiner));
    body += outcome_banner(result);
    body += summary_table(result);
    body += "<h2>Client under test</h2>\n" + declarations_table(client, provenance.declared_by);
    body += "<h2>Provenance</h2>\n" + provenance_table(provenance);
    body += "<h2>Scenarios</h2>\n" + case_filters();
    const auto wire = [&](const conf::CaseResult& c) { return wire_html(c, transcripts); };
    for (const auto& suite : result.suites) {
        body += fmt::format("<section class=\"suite\">\n<h2>{}{}</h2>\n", html_escape(suite.name),
                            suite.title.empty() ? "" : ": " + html_escape(suite.title));
        body += case_table(suite, wire) + "</section>\n";
    }
    return html_page("mblab conform-client " + client.examiner, body);
}

}  // namespace mblab::web
