#include "load/report.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "conformance/evidence_text.hpp"
#include "conformance/reports.hpp"
#include "load/line_use.hpp"
#include "support/json_document.hpp"

namespace mblab::load {

namespace {

using nlohmann::json;
using std::chrono::microseconds;

constexpr std::size_t kNodesOnStatusLine = 4;
constexpr FailureKind kKinds[] = {FailureKind::Timeout,     FailureKind::Malformed,
                                  FailureKind::WrongAnswer, FailureKind::UnexpectedException,
                                  FailureKind::Refused,     FailureKind::Dropped};

double seconds(microseconds elapsed) {
    return static_cast<double>(elapsed.count()) / 1e6;
}
double millis(std::uint64_t micros) {
    return static_cast<double>(micros) / 1000.0;
}

std::string clock_text(std::chrono::milliseconds elapsed) {
    const auto s = elapsed.count() / 1000;
    return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
}

double rate(std::uint64_t count, microseconds elapsed) {
    return elapsed.count() > 0 ? static_cast<double>(count) / seconds(elapsed) : 0.0;
}

std::string plural(std::uint64_t n, std::string_view one, std::string_view many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
}

// "3 timeouts, 1 dropped connection"
std::string failure_breakdown(const NodeResult& node) {
    std::string out;
    for (FailureKind kind : kKinds) {
        const auto n = node.failures_of(kind);
        if (n == 0) continue;
        out += fmt::format("{}{} {}", out.empty() ? "" : ", ", n, failure_label(kind));
    }
    return out;
}

std::string traffic_text(const LoadPlan& plan) {
    const auto& s = plan.settings;
    if (s.connections == 0) return "none";
    std::string mix;
    for (const auto& entry : plan.mix) {
        mix += fmt::format("{}{}={}", mix.empty() ? "" : ",", entry.text, entry.weight);
    }
    return fmt::format("{} connections, mix {}, pipeline {}", s.connections, mix, s.pipeline);
}

std::string rate_text(const LoadPlan& plan) {
    return plan.settings.rate > 0
               ? fmt::format("at most {:g} requests/s in total", plan.settings.rate)
               : "as fast as answered";
}

std::string node_reason(const LoadPlan& plan, const NodeResult& node, bool interrupted) {
    if (node.failure_total() > 0) {
        std::string text = fmt::format(
            "{}: {}", plural(node.failure_total(), "failure", "failures"), failure_breakdown(node));
        if (node.first_failure) {
            const auto& first = *node.first_failure;
            text += fmt::format("; first at {:.3f} s{}: {}", seconds(first.at),
                                first.exchange.empty() ? "" : ", exchange " + first.exchange,
                                first.reason);
        }
        return text;
    }
    if (interrupted) return "stopped before the duration ended; no failure until then";
    return fmt::format("no failure in {}", format_duration_words(plan.settings.duration));
}

json latency_json(const LatencySnapshot& latency) {
    return {{"count", latency.count()},
            {"p50", millis(latency.percentile(0.50))},
            {"p90", millis(latency.percentile(0.90))},
            {"p99", millis(latency.percentile(0.99))},
            {"p99_9", millis(latency.percentile(0.999))},
            {"max", millis(latency.max())}};
}

// Conform's report shape for the evidence, taken from its own JSON writer.
std::vector<json> evidence_json(const LoadPlan& plan, const LoadResult& result) {
    std::vector<json> out;
    const json conform = json::parse(conformance::json_report(load_as_run(plan, result)));
    for (const auto& c : conform["suites"][0]["cases"]) {
        out.push_back(c["evidence"].empty() ? json() : c["evidence"][0]);
    }
    return out;
}

// A serial node's use of its line; nothing for Modbus/TCP and RTU over TCP.
std::optional<LineUse> node_line_use(const LoadPlan& plan, const LoadResult& result,
                                     std::size_t node) {
    if (node >= plan.targets.size()) return std::nullopt;
    const auto& line = plan.targets[node].line;
    if (!line || !line->serial) return std::nullopt;
    const NodeResult& counts = result.nodes[node];
    return line_use(*line->serial, counts.line_chars, counts.line_frames, result.elapsed);
}

json line_json(const std::optional<LineUse>& use) {
    if (!use) return nullptr;
    return {{"characters_per_s", use->chars_per_second},
            {"limit_per_s", use->limit_per_second},
            {"share", use->share},
            {"logical_timing", use->logical}};
}

json node_json(const LoadPlan& plan, const LoadResult& result, const NodeResult& node,
               json evidence, json line) {
    json failures = {{"total", node.failure_total()}};
    for (FailureKind kind : kKinds)
        failures[std::string(failure_key(kind))] = node.failures_of(kind);
    json exchanges = json::array();
    for (std::size_t i = 0; i < plan.exchanges.size(); ++i) {
        const auto& exchange = plan.exchanges[i];
        exchanges.push_back({{"name", exchange.name},
                             {"source", exchange.source},
                             {"function", exchange.function()},
                             {"sent", node.exchange_sent[i]},
                             {"failed", node.exchange_failed[i]}});
    }
    json left = json::array();
    for (const auto& na : node.not_applicable)
        left.push_back({{"id", na.id}, {"reason", na.reason}});
    json out = {{"target", node.target},
                {"verdict", load_verdict_label(node.verdict(result.interrupted))},
                {"requests", node.sent},
                {"answers", node.answered},
                {"late_answers", node.late},
                {"tls_handshakes", node.handshakes},
                {"tls_resumed", node.resumed},
                {"line", std::move(line)},
                {"requests_per_s", rate(node.answered, result.elapsed)},
                {"failures", failures},
                {"latency_ms", latency_json(node.latency)},
                {"exchanges", exchanges},
                {"not_applicable", left},
                {"first_failure", nullptr}};
    if (node.first_failure) {
        const auto& first = *node.first_failure;
        out["first_failure"] = {{"kind", failure_key(first.kind)},
                                {"at_s", seconds(first.at)},
                                {"exchange", first.exchange},
                                {"reason", first.reason},
                                {"evidence", std::move(evidence)}};
    }
    return out;
}

}  // namespace

std::string load_header(const LoadPlan& plan) {
    const auto& s = plan.settings;
    std::string out = fmt::format("mblab load: {} for {} (CTP 8: interoperability)\n",
                                  plural(plan.targets.size(), "node", "nodes"),
                                  format_duration_words(s.duration));
    if (s.tests && plan.test_exchanges > 0) {
        std::string suites;
        for (const auto& name : plan.suites)
            suites += (suites.empty() ? "" : ", ") + name;
        out += fmt::format("  protocol tests: {} from {} ({}), one connection (or line) per node\n",
                           plural(plan.cases.size(), "case", "cases"), suites,
                           plural(plan.test_exchanges, "exchange", "exchanges"));
    } else {
        out += "  protocol tests: none\n";
    }
    out += fmt::format("  traffic: {}; {}\n", traffic_text(plan), rate_text(plan));
    out += fmt::format("  timeout {} ms, {}\n", s.timeout.count(),
                       plural(s.threads, "thread", "threads"));
    if (s.tests && !plan.left_out.empty()) {
        std::string left;
        for (const auto& item : plan.left_out) {
            left += fmt::format("{}{} ({})", left.empty() ? "" : ", ", item.id, item.reason);
        }
        out += "  not in the loop: " + left + "\n";
    }
    if (s.tests && !plan.values_unchecked.empty()) {
        std::string names;
        for (const auto& name : plan.values_unchecked)
            names += (names.empty() ? "" : ", ") + name;
        out += "  read back without values (the mix writes there): " + names + "\n";
    }
    for (const auto& target : plan.targets)
        out += "  node " + target.url + "\n";
    return out;
}

std::string load_status_line(const LoadPlan& plan, const LoadStatus& status) {
    const auto left =
        std::max(plan.settings.duration - status.elapsed, std::chrono::milliseconds(0));
    std::string out =
        fmt::format("{} elapsed, {} left | {:.0f} req/s | {}", clock_text(status.elapsed),
                    clock_text(left), status.rate, plural(status.failures, "failure", "failures"));
    for (std::size_t i = 0; i < status.nodes.size() && i < kNodesOnStatusLine; ++i) {
        const auto& node = status.nodes[i];
        out += fmt::format(" | {} {:.0f}/s p50 {:.2f} p99 {:.2f} ms{}", plan.targets[i].url,
                           node.rate, millis(node.p50_us), millis(node.p99_us),
                           node.failures > 0 ? fmt::format(" {} FAILED", node.failures) : "");
    }
    if (status.nodes.size() > kNodesOnStatusLine) {
        out += fmt::format(" | +{} nodes", status.nodes.size() - kNodesOnStatusLine);
    }
    return out;
}

std::string load_summary(const LoadPlan& plan, const LoadResult& result) {
    std::size_t width = 4;
    for (const auto& node : result.nodes)
        width = std::max(width, node.target.size());
    std::string out = fmt::format(
        "\n{:<{}}  {:>10}  {:>9}  {:>8}  {:>7}  {:>9}  {:>5}  {:>9}  {:>7}  {:>7}  "
        "{:>8}  {:>8}  {:>8}  {:>8}  {:>8}  {}\n",
        "node", width, "requests", "answers/s", "failures", "timeout", "malformed", "wrong",
        "exception", "refused", "dropped", "p50 ms", "p90 ms", "p99 ms", "p99.9 ms", "max ms",
        "verdict");
    for (const auto& node : result.nodes) {
        const auto& l = node.latency;
        out += fmt::format(
            "{:<{}}  {:>10}  {:>9.0f}  {:>8}  {:>7}  {:>9}  {:>5}  {:>9}  {:>7}  {:>7}  "
            "{:>8.3f}  {:>8.3f}  {:>8.3f}  {:>8.3f}  {:>8.3f}  {}\n",
            node.target, width, node.sent, rate(node.answered, result.elapsed),
            node.failure_total(), node.failures_of(FailureKind::Timeout),
            node.failures_of(FailureKind::Malformed), node.failures_of(FailureKind::WrongAnswer),
            node.failures_of(FailureKind::UnexpectedException),
            node.failures_of(FailureKind::Refused), node.failures_of(FailureKind::Dropped),
            millis(l.percentile(0.50)), millis(l.percentile(0.90)), millis(l.percentile(0.99)),
            millis(l.percentile(0.999)), millis(l.max()),
            load_verdict_label(node.verdict(result.interrupted)));
    }
    for (std::size_t i = 0; i < result.nodes.size(); ++i) {
        if (const auto use = node_line_use(plan, result, i)) {
            out += fmt::format("{}: line use {}\n", result.nodes[i].target,
                               line_use_text(*plan.targets[i].line->serial, *use));
        }
    }
    for (const auto& node : result.nodes) {
        if (node.handshakes == 0) continue;
        out += fmt::format("{}: {} TLS handshakes, {} of them resumed\n", node.target,
                           node.handshakes, node.resumed);
    }
    for (const auto& node : result.nodes) {
        for (const auto& na : node.not_applicable) {
            out += fmt::format("\n{}: {} left the loop: {}\n", node.target, na.id, na.reason);
        }
        if (node.failure_total() == 0) continue;
        out += fmt::format("\n{}: FAIL, {}\n", node.target, node_reason(plan, node, false));
        if (node.first_failure) {
            for (const auto& line : conformance::evidence_lines(node.first_failure->evidence)) {
                out += "    " + line + "\n";
            }
        }
        std::string by_exchange;
        for (std::size_t i = 0; i < plan.exchanges.size(); ++i) {
            if (node.exchange_failed[i] == 0) continue;
            by_exchange +=
                fmt::format("{}{} {} of {}", by_exchange.empty() ? "" : ", ",
                            plan.exchanges[i].name, node.exchange_failed[i], node.exchange_sent[i]);
        }
        if (!by_exchange.empty()) out += "  failed exchanges: " + by_exchange + "\n";
    }

    const auto elapsed = seconds(result.elapsed);
    out += fmt::format("\n{} requests, {} answers in {:.1f} s ({:.0f} answers/s)\n", result.sent(),
                       result.answered(), elapsed, rate(result.answered(), result.elapsed));
    switch (result.verdict()) {
        case LoadVerdict::Pass:
            out += fmt::format("PASS: no failure on {} in {} under load (CTP 8.4)\n",
                               plural(result.nodes.size(), "node", "nodes"),
                               format_duration_words(plan.settings.duration));
            break;
        case LoadVerdict::Fail: {
            std::string failed;
            std::size_t count = 0;
            for (const auto& node : result.nodes) {
                if (node.failure_total() == 0) continue;
                failed += (failed.empty() ? "" : ", ") + node.target;
                ++count;
            }
            out += fmt::format("FAIL: {} of {} failed ({}); {}\n", count,
                               plural(result.nodes.size(), "node", "nodes"), failed,
                               plural(result.failures(), "failure", "failures"));
            break;
        }
        case LoadVerdict::Incomplete:
            out += fmt::format(
                "INCOMPLETE: stopped after {:.1f} s of {}; no failure so far, but CTP 8.4 "
                "asks for the whole duration\n",
                elapsed, format_duration_words(plan.settings.duration));
            break;
    }
    return out;
}

conformance::RunResult load_as_run(const LoadPlan& plan, const LoadResult& result) {
    conformance::RunResult run;
    run.target = result.nodes.size() == 1 ? result.nodes.front().target
                                          : plural(result.nodes.size(), "node", "nodes");
    run.elapsed = result.elapsed;
    run.requests = result.sent();
    conformance::SuiteResult suite{"load", "Interoperability test under load (CTP 8)", "", {}};
    for (const auto& node : result.nodes) {
        conformance::CaseResult c;
        c.id = node.target;
        c.source = "CTP 8.4";
        c.title = fmt::format("no failure for {} under load",
                              format_duration_words(plan.settings.duration));
        c.elapsed = result.elapsed;
        c.requests = node.sent;
        c.outcome.reason = node_reason(plan, node, result.interrupted);
        switch (node.verdict(result.interrupted)) {
            case LoadVerdict::Pass:
                c.outcome.verdict = conformance::Verdict::Pass;
                break;
            case LoadVerdict::Incomplete:
                c.outcome.verdict = conformance::Verdict::NotRun;
                break;
            case LoadVerdict::Fail:
                c.outcome.verdict = conformance::Verdict::Fail;
                if (node.first_failure) c.outcome.evidence.push_back(node.first_failure->evidence);
                break;
        }
        suite.cases.push_back(std::move(c));
    }
    run.suites.push_back(std::move(suite));
    return run;
}

std::string load_json_report(const LoadPlan& plan, const LoadResult& result) {
    const auto& s = plan.settings;
    std::string mix;
    for (const auto& entry : plan.mix) {
        mix += fmt::format("{}{}={}", mix.empty() ? "" : ",", entry.text, entry.weight);
    }
    json cases = json::array();
    for (const auto& c : plan.cases)
        cases.push_back(c.id);
    json left = json::array();
    for (const auto& item : plan.left_out)
        left.push_back({{"id", item.id}, {"reason", item.reason}});
    auto evidence = evidence_json(plan, result);
    json nodes = json::array();
    for (std::size_t i = 0; i < result.nodes.size(); ++i) {
        nodes.push_back(node_json(plan, result, result.nodes[i], std::move(evidence[i]),
                                  line_json(node_line_use(plan, result, i))));
    }
    json report = {{"tool", "mblab load"},
                   {"verdict", load_verdict_label(result.verdict())},
                   {"passed", result.verdict() == LoadVerdict::Pass},
                   {"interrupted", result.interrupted},
                   {"duration_s", static_cast<double>(s.duration.count()) / 1000.0},
                   {"elapsed_s", seconds(result.elapsed)},
                   {"settings",
                    {{"connections", s.connections},
                     {"rate", s.rate},
                     {"mix", s.connections > 0 ? json(mix) : json()},
                     {"pipeline", s.pipeline},
                     {"timeout_ms", s.timeout.count()},
                     {"threads", s.threads},
                     {"seed", s.seed},
                     {"tests", s.tests && plan.test_exchanges > 0},
                     {"suites", plan.suites},
                     {"cases", cases},
                     {"left_out", left},
                     {"values_unchecked", plan.values_unchecked}}},
                   {"totals",
                    {{"requests", result.sent()},
                     {"answers", result.answered()},
                     {"failures", result.failures()},
                     {"requests_per_s", rate(result.answered(), result.elapsed)}}},
                   {"nodes", nodes}};
    return json_document(report) + "\n";
}

std::string load_junit_report(const LoadPlan& plan, const LoadResult& result) {
    std::string xml = conformance::junit_report(load_as_run(plan, result));
    // The conformance writer names its own tool in the outer element.
    const std::string_view theirs = "<testsuites name=\"mblab conform ";
    if (auto at = xml.find(theirs); at != std::string::npos) {
        xml.replace(at, theirs.size(), "<testsuites name=\"mblab load ");
    }
    return xml;
}

}  // namespace mblab::load
