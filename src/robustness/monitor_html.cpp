#include "robustness/monitor_html.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/reports.hpp"
#include "protocol/function_table.hpp"
#include "robustness/iec62443_report.hpp"
#include "robustness/ladder_report.hpp"
#include "robustness/reproducer.hpp"

namespace mblab::robustness {

namespace {

using conformance::xml_escape;

constexpr double kWidth = 900;
constexpr double kHeight = 240;
constexpr double kLeft = 50;  // room for the latency axis's labels

double seconds_between(Clock::time_point from, Clock::time_point to) {
    return std::chrono::duration<double>(to - from).count();
}

// The latency chart: a point per cycle that held, a red mark along the top per cycle missed, the
// budget as a dashed line, and each phase's start as a labelled vertical line.
std::string chart(const MonitorJudgement& judged, const MonitorSpec& spec,
                  const std::vector<MonitorCycle>& cycles) {
    if (cycles.empty() || judged.phases.empty()) return "<p>No cycle was run.</p>\n";
    const auto origin = judged.phases.front().phase.begin;
    const double span = std::max(0.001, seconds_between(origin, judged.phases.back().phase.end));
    // The scale reaches the budget, so a miss of it is always on the chart.
    double top = static_cast<double>(spec.budget.count());
    for (const auto& c : cycles) {
        if (c.held()) top = std::max(top, static_cast<double>(c.latency->count()) / 1000.0);
    }
    const auto x = [&](Clock::time_point at) {
        return kLeft + (kWidth - kLeft) * seconds_between(origin, at) / span;
    };
    const auto y = [&](double ms) { return kHeight - 20 - (kHeight - 40) * ms / top; };
    std::string out = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" role=\"img\" "
        "aria-label=\"monitor latency over time\">\n",
        kWidth, kHeight);
    out += fmt::format(
        "<text x=\"4\" y=\"{:.1f}\" font-size=\"11\">{:.1f} ms</text>\n<text x=\"4\" y=\"{:.1f}\" "
        "font-size=\"11\">0</text>\n",
        y(top) + 4, top, y(0) + 4);
    out += fmt::format(
        "<line x1=\"{}\" y1=\"{:.1f}\" x2=\"{}\" y2=\"{:.1f}\" stroke=\"#c60\" "
        "stroke-dasharray=\"4 3\"/><text x=\"{}\" y=\"{:.1f}\" font-size=\"11\" "
        "fill=\"#c60\">budget {} ms</text>\n",
        kLeft, y(static_cast<double>(spec.budget.count())), kWidth,
        y(static_cast<double>(spec.budget.count())), kWidth - 90,
        y(static_cast<double>(spec.budget.count())) - 3, spec.budget.count());
    for (const auto& p : judged.phases) {
        out += fmt::format(
            "<line x1=\"{0:.1f}\" y1=\"10\" x2=\"{0:.1f}\" y2=\"{1}\" stroke=\"#888\"/><text "
            "x=\"{2:.1f}\" y=\"{3}\" font-size=\"11\">{4}</text>\n",
            x(p.phase.begin), kHeight - 20, x(p.phase.begin) + 3, kHeight - 5,
            xml_escape(p.phase.name));
    }
    std::string points;
    for (const auto& c : cycles) {
        if (c.held()) {
            points += fmt::format("{:.1f},{:.1f} ", x(c.started),
                                  y(static_cast<double>(c.latency->count()) / 1000.0));
        } else if (!c.pending()) {
            out += fmt::format(
                "<rect x=\"{:.1f}\" y=\"8\" width=\"3\" height=\"10\" fill=\"#d00\"><title>{}"
                "</title></rect>\n",
                x(c.started), xml_escape(c.missed));
        }
    }
    out += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"#06c\"/>\n", points);
    out += "</svg>\n";
    return out;
}

// The request storms per function code, a row each: the highest rate held and the first lost,
// or why the storm did not run.
std::string per_function_table(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                               const std::vector<StormNotRun>& not_run) {
    std::string rows;
    const auto all = storm_summaries(judged, rungs);
    const auto rate = [](const std::optional<double>& r) {
        return r ? fmt::format("{:g}/s", *r) : std::string("-");
    };
    for (const auto kind : request_storms()) {
        const auto function = storm_words(kind).function;
        const auto name = xml_escape(
            fmt::format("FC {:02X} {}", function, protocol::find_function(function)->name));
        for (const auto& s : all) {
            if (s.kind == kind)
                rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", name,
                                    rate(s.highest_held), rate(s.lost_at), storm_tag(kind));
        }
        for (const auto& n : not_run) {
            if (n.kind == kind)
                rows += fmt::format("<tr><td>{}</td><td colspan=\"3\">not run: {}</td></tr>\n",
                                    name, xml_escape(n.reason));
        }
    }
    if (rows.empty()) return rows;
    return "<h3>Requests per second per function code</h3>\n<table><tr><th>function</th>"
           "<th>highest rate held</th><th>lost at</th><th>IEC 62443-4-2</th></tr>\n" +
           rows + "</table>\n";
}

}  // namespace

std::string monitor_html(const FuzzResult& result, const MonitorJudgement& judged,
                         const MonitorSpec& spec, const std::vector<MonitorCycle>& cycles,
                         const std::vector<LadderRung>& rungs,
                         const std::vector<StormNotRun>& not_run) {
    std::string out = fmt::format(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>mblab fuzz "
        "{0}</title>\n<style>body{{font-family:sans-serif;margin:2em}}table{{border-collapse:"
        "collapse}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:left}}"
        "pre{{background:#f4f4f4;padding:6px}}</style></head><body>\n<h1>mblab fuzz {0}</h1>\n",
        xml_escape(result.target));
    out += fmt::format("<p><strong>Verdict: {}</strong>: {}</p>\n", verdict_name(judged.verdict),
                       xml_escape(judged.why));
    out += fmt::format(
        "<p>Essential-function monitor: {} register {} every {} ms, budget {} ms, {}% missed "
        "tolerated. Latency of each cycle that held (blue), each cycle missed (red, its reason "
        "on hover):</p>\n",
        spec.read_only ? "FC 03 of" : "FC 06 then FC 03 read-back of", spec.address,
        spec.period.count(), spec.budget.count(), spec.miss_percent);
    out += chart(judged, spec, cycles);
    out +=
        "<h2>Phases</h2>\n<table><tr><th>phase</th><th>cycles</th><th>missed</th><th>median "
        "ms</th><th>worst ms</th><th>monitor</th><th>IEC 62443-4-2</th></tr>\n";
    for (const auto& p : judged.phases) {
        out += fmt::format(
            "<tr><td>{}</td><td>{}</td><td>{} ({:.1f}%)</td><td>{:.2f}</td><td>{:.2f}</td><td>{}"
            "</td><td>{}</td></tr>\n",
            xml_escape(p.phase.name), p.cycles, p.missed, p.missed_percent,
            static_cast<double>(p.median.count()) / 1000.0,
            static_cast<double>(p.worst.count()) / 1000.0, p.held ? "held" : "lost",
            xml_escape(p.phase.requirement));
    }
    out += "</table>\n";
    if (!judged.missed_during.empty()) {
        out +=
            "<h2>Cases during which the monitor missed cycles</h2>\n<table><tr><th>case</th>"
            "<th>class</th><th>name</th><th>missed</th><th>the first's reason</th></tr>\n";
        for (const auto& d : judged.missed_during) {
            out += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                               d.case_number, class_name(d.kind), xml_escape(d.case_name), d.missed,
                               xml_escape(d.reason));
        }
        out += "</table>\n";
    }
    if (!rungs.empty() || !not_run.empty())
        out += "<h2>Storm ladders</h2>\n<pre>" + xml_escape(ladder_text(judged, rungs, not_run)) +
               "</pre>\n" + per_function_table(judged, rungs, not_run);
    out += "<h2>Findings</h2>\n";
    if (result.findings.empty()) out += "<p>None: the device served every liveness check.</p>\n";
    for (const auto& f : result.findings) {
        out += fmt::format("<h3>{}: {} [{}]</h3>\n<p>The device {}. {}</p>\n<pre>{}</pre>\n",
                           class_name(f.kind), xml_escape(f.case_name), requirement_of(f.kind),
                           xml_escape(f.reason), xml_escape(f.minimise_note),
                           xml_escape(reproducer_text(f.reproducer, "")));
    }
    out += fmt::format("<p>Out of scope: {}.</p>\n</body></html>\n", kOutOfScope);
    return out;
}

}  // namespace mblab::robustness
