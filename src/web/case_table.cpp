#include "web/case_table.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/evidence_text.hpp"
#include "conformance/line_evidence.hpp"
#include "conformance/references.hpp"
#include "support/name_table.hpp"
#include "web/page.hpp"

namespace mblab::web {

namespace {

namespace conf = mblab::conformance;

// evidence_lines lays a frame out after a 10-character label, each byte two columns where
// frame_column says; the ^^ line under them marks the same columns.
constexpr std::size_t kLabelWidth = 10;

// `line` escaped, the two characters of each byte in `cells` (below `count`) wrapped in <mark>.
std::string marked_line(const std::string& line, const std::vector<std::size_t>& cells,
                        std::size_t count, client::Framing framing) {
    std::vector<bool> marked(line.size(), false);
    for (std::size_t cell : cells) {
        if (cell >= count) continue;
        const std::size_t column = kLabelWidth + conf::frame_column(framing, cell);
        for (std::size_t i = column; i < column + 2 && i < line.size(); ++i)
            marked[i] = true;
    }
    std::string out;
    for (std::size_t i = 0; i < line.size(); ++i) {
        if (marked[i] && (i == 0 || !marked[i - 1])) out += "<mark class=\"diff\">";
        out += html_escape(std::string_view(&line[i], 1));
        if (marked[i] && (i + 1 == line.size() || !marked[i + 1])) out += "</mark>";
    }
    return out;
}

// Each citation of a case's source links to its document, the section in the link's title (the
// documents are PDFs without anchors; RFCs have them).
std::string source_html(std::string_view source) {
    std::string out;
    for (const auto& citation : conf::citations(source)) {
        if (!out.empty()) out += "; ";
        out += citation.url.empty()
                   ? html_escape(citation.text)
                   : fmt::format("<a href=\"{}\" title=\"{}\">{}</a>", html_escape(citation.url),
                                 html_escape(citation.title), html_escape(citation.text));
    }
    return out;
}

constexpr conf::Verdict kVerdicts[] = {conf::Verdict::Pass, conf::Verdict::Fail,
                                       conf::Verdict::NotApplicable, conf::Verdict::NotRun};

}  // namespace

std::string_view verdict_class(conf::Verdict verdict) {
    static constexpr Named<conf::Verdict> kNames[] = {{conf::Verdict::Pass, "PASS"},
                                                      {conf::Verdict::Fail, "FAIL"},
                                                      {conf::Verdict::NotApplicable, "NA"},
                                                      {conf::Verdict::NotRun, "NOTRUN"}};
    return name_of(kNames, verdict, "NOTRUN");
}

std::string evidence_html(const conf::Exchange& exchange) {
    const auto lines = conf::evidence_lines(exchange);
    // As in evidence_lines: only a received frame is compared byte by byte.
    const bool compared = !exchange.received.empty() && !exchange.match.differs.empty();
    const auto& differs = exchange.match.differs;
    std::string out = "<pre class=\"evidence\">";
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (compared && i == 1) {
            out += marked_line(lines[i], differs,
                               conf::frame_cells(exchange.framing, exchange.received),
                               exchange.framing);
        } else if (compared && i == 2) {
            out += marked_line(lines[i], differs, exchange.match.expected_cells.size(),
                               exchange.framing);
        } else {
            out += html_escape(lines[i]);
        }
        out += '\n';
    }
    return out + "</pre>\n";
}

std::string case_table(const conf::SuiteResult& suite) {
    std::string out =
        "<table class=\"cases\">\n<thead><tr><th>case</th><th>verdict</th><th>title</th>"
        "<th>reason</th><th>source</th></tr></thead>\n";
    for (const auto& c : suite.cases) {
        const auto& outcome = c.outcome;
        out += fmt::format(
            "<tbody class=\"case\" data-verdict=\"{}\" data-id=\"{}\">\n<tr><td>{}</td>"
            "<td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            html_escape(conf::verdict_label(outcome.verdict)), html_escape(c.id), html_escape(c.id),
            verdict_class(outcome.verdict), html_escape(conf::verdict_label(outcome.verdict)),
            html_escape(c.title), html_escape(outcome.reason), source_html(c.source));
        if (!outcome.evidence.empty()) {
            out += "<tr><td></td><td colspan=\"4\">";
            for (const auto& exchange : outcome.evidence)
                out += evidence_html(exchange);
            out += "</td></tr>\n";
        }
        out += "</tbody>\n";
    }
    return out + "</table>\n";
}

std::string case_filters() {
    std::string out = "<div class=\"controls\">\n";
    for (conf::Verdict verdict : kVerdicts) {
        const auto label = html_escape(conf::verdict_label(verdict));
        out += fmt::format(
            "<label><input type=\"checkbox\" class=\"verdict-filter\" value=\"{}\" checked> "
            "<span class=\"{}\">{}</span></label>\n",
            label, verdict_class(verdict), label);
    }
    out +=
        "<label>case id <input type=\"search\" id=\"search\" placeholder=\"e.g. 7.5\"></label>\n"
        "<span id=\"shown\"></span>\n</div>\n";
    return out;
}

}  // namespace mblab::web
