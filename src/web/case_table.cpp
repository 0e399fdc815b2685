#include "web/case_table.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/evidence_text.hpp"
#include "conformance/references.hpp"
#include "support/name_table.hpp"
#include "web/page.hpp"

namespace mblab::web {

namespace {

namespace conf = mblab::conformance;

// `line` escaped, its marked columns wrapped in <mark>.
std::string marked_line(const conf::EvidenceLine& line) {
    std::string out;
    std::size_t at = 0;
    for (const auto& [first, last] : line.marked) {
        out += html_escape(std::string_view(line.text).substr(at, first - at));
        out += "<mark class=\"diff\">" +
               html_escape(std::string_view(line.text).substr(first, last - first)) + "</mark>";
        at = last;
    }
    return out + html_escape(std::string_view(line.text).substr(at));
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
    std::string out = "<pre class=\"evidence\">";
    for (const auto& line : conf::evidence_layout(exchange)) {
        // The marks show which bytes differ; a ^^ line would not stay under them once the
        // browser wraps a long frame.
        if (line.text.find_first_not_of(" ^") == std::string::npos) continue;
        out += marked_line(line) + '\n';
    }
    return out + "</pre>\n";
}

namespace {

// The one row of a suite that cannot apply: its case ids all in data-id, so the search by id
// still finds it; the sources its cases cite, each once.
std::string inapplicable_row(const conf::SuiteResult& suite, const conf::Inapplicable& why) {
    std::string ids;
    std::vector<std::string_view> sources;
    for (const auto& c : suite.cases) {
        ids += (ids.empty() ? "" : " ") + c.id;
        if (std::find(sources.begin(), sources.end(), c.source) == sources.end())
            sources.push_back(c.source);
    }
    std::string cited;
    for (const auto source : sources)
        cited += (cited.empty() ? "" : "; ") + source_html(source);
    const auto label = html_escape(conf::verdict_label(conf::Verdict::NotApplicable));
    return fmt::format(
        "<tbody class=\"case\" data-verdict=\"{}\" data-id=\"{}\">\n<tr><td>{}</td>"
        "<td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n</tbody>\n",
        label, html_escape(ids), html_escape(fmt::format("all {}", suite.cases.size())),
        verdict_class(conf::Verdict::NotApplicable), label, html_escape(why.title),
        html_escape(why.reason), cited);
}

}  // namespace

std::string case_table(const conf::SuiteResult& suite,
                       const std::function<std::string(const conf::CaseResult&)>& more) {
    std::string out =
        "<table class=\"cases\">\n<thead><tr><th>case</th><th>verdict</th><th>title</th>"
        "<th>reason</th><th>source</th></tr></thead>\n";
    if (const auto why = conf::suite_inapplicable(suite.name, suite.cases))
        return out + inapplicable_row(suite, *why) + "</table>\n";
    for (const auto& c : suite.cases) {
        const auto& outcome = c.outcome;
        out += fmt::format(
            "<tbody class=\"case\" data-verdict=\"{}\" data-id=\"{}\">\n<tr><td>{}</td>"
            "<td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            html_escape(conf::verdict_label(outcome.verdict)), html_escape(c.id), html_escape(c.id),
            verdict_class(outcome.verdict), html_escape(conf::verdict_label(outcome.verdict)),
            html_escape(c.title), html_escape(outcome.reason), source_html(c.source));
        std::string evidence;
        for (const auto& exchange : outcome.evidence)
            evidence += evidence_html(exchange);
        if (more) evidence += more(c);
        if (!evidence.empty()) out += "<tr><td></td><td colspan=\"4\">" + evidence + "</td></tr>\n";
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
