#include "web/load_html.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "load/histogram.hpp"
#include "load/report.hpp"
#include "web/case_table.hpp"
#include "web/page.hpp"

namespace mblab::web {

namespace {

using nlohmann::json;

constexpr int kWidth = 640;
constexpr int kHeight = 200;
constexpr int kLeft = 70;    // room for the count axis and its title
constexpr int kBottom = 40;  // room for the latency axis, its ticks and title
constexpr int kTop = 10;

double millis(std::uint64_t micros) {
    return static_cast<double>(micros) / 1000.0;
}

std::string cell(const json& value) {
    if (value.is_number_float()) return fmt::format("{:.3f}", value.get<double>());
    if (value.is_string()) return html_escape(value.get<std::string>());
    return html_escape(value.dump());
}

std::string number_cell(const json& value) {
    return "<td class=\"number\">" + cell(value) + "</td>";
}

// The failure kinds some node counted: a column each (none on a clean run), so the latency
// columns stay on a 1280-pixel screen.
std::vector<std::string> kinds_seen(const json& report) {
    std::vector<std::string> kinds;
    for (const auto& [kind, count] : report["nodes"][0]["failures"].items()) {
        if (kind == "total") continue;
        for (const json& node : report["nodes"]) {
            if (node["failures"][kind].get<std::uint64_t>() > 0) {
                kinds.push_back(kind);
                break;
            }
        }
    }
    return kinds;
}

std::string nodes_table(const json& report) {
    const auto kinds = kinds_seen(report);
    std::string out =
        "<table id=\"nodes\">\n<tr><th>node</th><th>requests</th><th>answers</th>"
        "<th>answers/s</th><th>failures</th>";
    for (const auto& kind : kinds)
        out += "<th>" + html_escape(kind) + "</th>";
    out +=
        "<th>p50 ms</th><th>p90 ms</th><th>p99 ms</th><th>p99.9 ms</th><th>max ms</th>"
        "<th>verdict</th></tr>\n";
    for (const json& node : report["nodes"]) {
        const std::string verdict = node["verdict"];
        out +=
            "<tr class=\"node\"><td>" + cell(node["target"]) + "</td>" +
            number_cell(node["requests"]) + number_cell(node["answers"]) +
            fmt::format("<td class=\"number\">{:.0f}</td>", node["requests_per_s"].get<double>()) +
            number_cell(node["failures"]["total"]);
        for (const auto& kind : kinds)
            out += number_cell(node["failures"][kind]);
        for (const char* key : {"p50", "p90", "p99", "p99_9", "max"})
            out += number_cell(node["latency_ms"][key]);
        out += fmt::format("<td class=\"{}\">{}</td></tr>\n", html_escape(verdict),
                           html_escape(verdict));
    }
    return out + "</table>\n";
}

std::string exchanges_table(const json& node) {
    std::string out =
        "<table class=\"exchanges\">\n<tr><th>exchange</th><th>function</th><th>source</th>"
        "<th>sent</th><th>failed</th></tr>\n";
    for (const json& exchange : node["exchanges"]) {
        out += "<tr><td>" + cell(exchange["name"]) + "</td><td>" + cell(exchange["function"]) +
               "</td><td>" + cell(exchange["source"]) + "</td>" + number_cell(exchange["sent"]) +
               number_cell(exchange["failed"]) + "</tr>\n";
    }
    return out + "</table>\n";
}

std::string banner(const json& report) {
    const std::string verdict = report["verdict"];
    std::string text = verdict;
    if (report["interrupted"].get<bool>()) {
        text += fmt::format(": interrupted after {:.1f} s of {:g} s",
                            report["elapsed_s"].get<double>(), report["duration_s"].get<double>());
    }
    return fmt::format("<p class=\"banner {}\" id=\"outcome\">{}</p>\n", html_escape(verdict),
                       html_escape(text));
}

}  // namespace

std::string latency_svg(const load::LatencySnapshot& latency, std::size_t bars) {
    using load::LatencyBuckets;
    std::size_t first = LatencyBuckets::kCount;
    std::size_t last = 0;
    for (std::size_t i = 0; i < LatencyBuckets::kCount; ++i) {
        if (latency.in_bucket(i) == 0) continue;
        first = std::min(first, i);
        last = i;
    }
    std::string out = fmt::format(
        "<svg class=\"histogram\" width=\"{}\" height=\"{}\" "
        "viewBox=\"0 0 {} {}\" role=\"img\">\n",
        kWidth, kHeight, kWidth, kHeight);
    if (first > last) {
        out += fmt::format("<text x=\"{}\" y=\"{}\">no answers</text>\n", kLeft, kHeight / 2);
        return out + "</svg>\n";
    }
    // Bars of equal runs of buckets: fine-grained where the buckets are (1 us below 128 us, 1/64
    // of the value above), so the axis is linear at first and logarithmic after.
    const std::size_t span = last - first + 1;
    const std::size_t per_bar = (span + bars - 1) / bars;
    const std::size_t count = (span + per_bar - 1) / per_bar;
    std::vector<std::uint64_t> heights(count, 0);
    for (std::size_t i = first; i <= last; ++i)
        heights[(i - first) / per_bar] += latency.in_bucket(i);
    const std::uint64_t tallest = *std::max_element(heights.begin(), heights.end());
    const double plot_width = kWidth - kLeft - 10;
    const double plot_height = kHeight - kTop - kBottom;
    const double bar_width = plot_width / static_cast<double>(count);
    auto lower_ms = [&](std::size_t bar) {
        const std::size_t index = first + bar * per_bar;
        return index == 0 ? 0.0 : millis(LatencyBuckets::upper(index - 1) + 1);
    };
    auto upper_ms = [&](std::size_t bar) {
        // As the percentiles: never above the largest value seen.
        return millis(std::min(
            LatencyBuckets::upper(std::min(last, first + (bar + 1) * per_bar - 1)), latency.max()));
    };
    for (std::size_t bar = 0; bar < count; ++bar) {
        const double height =
            plot_height * static_cast<double>(heights[bar]) / static_cast<double>(tallest);
        out += fmt::format(
            "<rect class=\"bar\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\">"
            "<title>{:.3f}-{:.3f} ms: {} answers</title></rect>\n",
            kLeft + bar_width * static_cast<double>(bar), kTop + plot_height - height,
            std::max(bar_width - 1.0, 1.0), height, lower_ms(bar), upper_ms(bar), heights[bar]);
    }
    const double axis = kTop + plot_height;
    // Both axes drawn and named: answers per bar up the side, latency along the bottom with a
    // tick at each fifth of the bars.
    out += fmt::format(
        "<line x1=\"{}\" y1=\"{:.1f}\" x2=\"{}\" y2=\"{:.1f}\" stroke=\"#333\"/>\n"
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{:.1f}\" stroke=\"#333\"/>\n"
        "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>"
        "<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">0</text>\n"
        "<text class=\"axis-title\" transform=\"translate(12 {:.1f}) rotate(-90)\" "
        "text-anchor=\"middle\">answers</text>\n",
        kLeft, axis, kWidth - 10, axis, kLeft, kTop, kLeft, axis, kLeft - 4, kTop + 10, tallest,
        kLeft - 4, axis, kTop + plot_height / 2);
    for (std::size_t tick = 0; tick <= 4; ++tick) {
        const std::size_t bar = std::min(count - 1, tick * count / 4);
        const bool last_tick = tick == 4;
        const double x = kLeft + bar_width * static_cast<double>(last_tick ? count : bar);
        out += fmt::format(
            "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#333\"/>"
            "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"{}\">{:.3f}</text>\n",
            x, axis, x, axis + 4, x, axis + 16,
            tick == 0   ? "start"
            : last_tick ? "end"
                        : "middle",
            last_tick ? upper_ms(count - 1) : lower_ms(bar));
    }
    out += fmt::format(
        "<text class=\"axis-title\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">latency "
        "(ms)</text>\n",
        kLeft + plot_width / 2, kHeight - 4);
    return out + "</svg>\n";
}

std::string load_html_report(const load::LoadPlan& plan, const load::LoadResult& result) {
    const json report = json::parse(load::load_json_report(plan, result));
    const auto run = load::load_as_run(plan, result);
    std::string body = "<h1>mblab load</h1>\n" + banner(report);
    body += "<pre id=\"plan\">" + html_escape(load::load_header(plan)) + "</pre>\n";
    const json& totals = report["totals"];
    body += fmt::format(
        "<p id=\"totals\">{} requests, {} answers, {} failures in {:.1f} s ({:.0f} "
        "answers/s)</p>\n",
        totals["requests"].get<std::uint64_t>(), totals["answers"].get<std::uint64_t>(),
        totals["failures"].get<std::uint64_t>(), report["elapsed_s"].get<double>(),
        totals["requests_per_s"].get<double>());
    body += "<h2>Nodes</h2>\n" + nodes_table(report);
    body += "<h2>Verdict per node</h2>\n" + case_filters() + case_table(run.suites.front());
    for (std::size_t i = 0; i < result.nodes.size(); ++i) {
        const json& node = report["nodes"][i];
        body += fmt::format("<section class=\"node-detail\">\n<h2>{}</h2>\n",
                            html_escape(result.nodes[i].target));
        body += "<h3>Latency</h3>\n" + latency_svg(result.nodes[i].latency);
        body += "<h3>Exchanges</h3>\n" + exchanges_table(node);
        for (const json& left : node["not_applicable"]) {
            body +=
                "<p>left the loop: " + cell(left["id"]) + ": " + cell(left["reason"]) + "</p>\n";
        }
        body += "</section>\n";
    }
    return html_page("mblab load", body);
}

}  // namespace mblab::web
