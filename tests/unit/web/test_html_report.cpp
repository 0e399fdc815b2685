#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "conformance/pattern.hpp"
#include "load/histogram.hpp"
#include "support/hex.hpp"
#include "web/case_table.hpp"
#include "web/html_report.hpp"
#include "web/load_html.hpp"
#include "web/page.hpp"

namespace mblab::web {
namespace {

namespace conf = mblab::conformance;
using test::hex;

conf::Exchange failed_read() {
    conf::Exchange exchange;
    exchange.sent = hex("00 00 00 00 00 06 01 01 00 00 00 01");
    exchange.status = client::ReceiveStatus::Frame;
    exchange.received = hex("00 01 00 00 00 04 01 01 01 00");
    exchange.expected = "00 00 00 00 00 04 01 01 01 XX";
    exchange.match =
        conf::match(conf::ResolvedPattern{conf::Pattern::parse(exchange.expected)->tokens()},
                    exchange.received);
    return exchange;
}

conf::RunResult sample_run() {
    conf::RunResult run;
    run.target = "tcp://127.0.0.1:1502";
    run.dut.registers = 100;
    run.dut.declared_by = "flags";
    run.requests = 12;
    conf::SuiteResult suite{"policy-2.1", "Policy", "policy-2.1.toml", {}};
    suite.cases.push_back(
        {"7.3.1", "CTP 7.3.1", "Read coils",
         conf::Outcome{conf::Verdict::Fail, "wrong transaction id", {failed_read()}},
         std::chrono::microseconds(1500), 1});
    suite.cases.push_back({"7.5.1", "CTP 7.5.1", "Read <registers> & \"more\"",
                           conf::Outcome{conf::Verdict::Pass, "", {}},
                           std::chrono::microseconds(500), 1});
    suite.cases.push_back({"7.13.1", "CTP 7.13.1", "Object messaging",
                           conf::Outcome{conf::Verdict::NotApplicable, "not declared", {}},
                           std::chrono::microseconds(0), 0});
    suite.cases.push_back({"7.2", "CTP 7.2", "Ping",
                           conf::Outcome{conf::Verdict::NotRun, "no ICMP socket", {}},
                           std::chrono::microseconds(0), 0});
    run.suites.push_back(suite);
    return run;
}

conf::Provenance sample_provenance() {
    conf::Provenance provenance;
    provenance.version = "0.1.0";
    provenance.commit = "abc1234";
    provenance.started = "2026-11-24T08:54:31Z";
    provenance.finished = "2026-11-24T08:54:33Z";
    provenance.command_line = {"mblab", "conform", "--case", "7.5.*"};
    provenance.declared_by = "flags";
    provenance.declarations = {{"unit", std::uint32_t{1}, "defaults"},
                               {"registers", std::uint32_t{100}, "flag --registers"}};
    provenance.device = {true, "Acme <&\"> Ltd", "MBLAB-REF", "0.1.0", ""};
    return provenance;
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(HtmlPage, EscapesMarkupCharacters) {
    EXPECT_EQ(html_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&apos;");
}

TEST(ConformHtml, HasEveryCaseWithItsVerdictForTheFilters) {
    const auto html = conform_html_report(sample_run(), sample_provenance());
    EXPECT_TRUE(html.starts_with("<!DOCTYPE html>"));
    EXPECT_TRUE(has(html, "<tbody class=\"case\" data-verdict=\"FAIL\" data-id=\"7.3.1\">"));
    EXPECT_TRUE(has(html, "<tbody class=\"case\" data-verdict=\"PASS\" data-id=\"7.5.1\">"));
    EXPECT_TRUE(has(html, "<tbody class=\"case\" data-verdict=\"N/A\" data-id=\"7.13.1\">"));
    EXPECT_TRUE(has(html, "<tbody class=\"case\" data-verdict=\"NOT RUN\" data-id=\"7.2\">"));
    for (const char* verdict : {"PASS", "FAIL", "N/A", "NOT RUN"}) {
        EXPECT_TRUE(has(html, std::string("class=\"verdict-filter\" value=\"") + verdict + "\""))
            << verdict;
    }
    EXPECT_TRUE(has(html, "<input type=\"search\" id=\"search\""));
    EXPECT_TRUE(has(html, "FAILED: 1 of 4 cases failed"));
}

TEST(ConformHtml, EscapesWhatTheDeviceAndTheCatalogueSay) {
    const auto html = conform_html_report(sample_run(), sample_provenance());
    EXPECT_TRUE(has(html, "<td>Acme &lt;&amp;&quot;&gt; Ltd</td>"));
    EXPECT_FALSE(has(html, "Acme <"));
    EXPECT_TRUE(has(html, "Read &lt;registers&gt; &amp; &quot;more&quot;"));
}

TEST(ConformHtml, CarriesDeclarationsIdentityAndProvenance) {
    const auto html = conform_html_report(sample_run(), sample_provenance());
    EXPECT_TRUE(has(html, "<tr><td>registers</td><td>100</td><td>flag --registers</td></tr>"));
    EXPECT_TRUE(has(html, "<tr><th>product code (object 01)</th><td>MBLAB-REF</td></tr>"));
    EXPECT_TRUE(has(html, "<tr><th>git commit</th><td>abc1234</td></tr>"));
    EXPECT_TRUE(
        has(html, "<tr><th>command line</th><td>mblab conform --case &apos;7.5.*&apos;</td>"));
    EXPECT_TRUE(has(html, "<tr><th>started</th><td>2026-11-24T08:54:31Z</td></tr>"));
}

// The console's lines, with the one differing byte (the transaction id's low byte) marked in the
// received and the expected line.
TEST(ConformHtml, MarksTheDifferingBytesOfAFailure) {
    EXPECT_EQ(evidence_html(failed_read()),
              "<pre class=\"evidence\">sent      00 00 00 00 00 06 01 01 00 00 00 01\n"
              "received  00 <mark class=\"diff\">01</mark> 00 00 00 04 01 01 01 00\n"
              "expected  00 <mark class=\"diff\">00</mark> 00 00 00 04 01 01 01 XX\n</pre>\n");
}

// A 250-byte answer of one repeated byte where 2 bytes were expected: the extra bytes are one
// cell, marked whole, and the evidence wraps instead of widening the table.
TEST(ConformHtml, MarksACompactedRunWholeAndWrapsTheEvidence) {
    conf::Exchange exchange;
    exchange.sent = hex("00 00 00 00 00 06 01 03 00 00 00 7D");
    exchange.status = client::ReceiveStatus::Frame;
    exchange.received = hex("00 00 00 00 00 FD 01 03 FA");
    exchange.received.insert(exchange.received.end(), 250, 0x5A);
    exchange.expected = "00 00 00 00 00 05 01 03 02 XX XX";
    exchange.match =
        conf::match(conf::ResolvedPattern{conf::Pattern::parse(exchange.expected)->tokens()},
                    exchange.received);
    const auto html = evidence_html(exchange);
    EXPECT_TRUE(has(html,
                    "received  00 00 00 00 00 <mark class=\"diff\">FD</mark> 01 03 "
                    "<mark class=\"diff\">FA</mark> 5A 5A <mark class=\"diff\">5A "
                    "x248</mark>\n"))
        << html;
    const auto page = conform_html_report(sample_run(), sample_provenance());
    EXPECT_TRUE(has(page, "pre.evidence { white-space: pre-wrap; overflow-wrap: anywhere; }"));
    EXPECT_TRUE(has(page,
                    "table.cases td:nth-child(4), table.cases td:nth-child(5) { "
                    "overflow-wrap: anywhere; }"));
}

TEST(ConformHtml, ASuiteThatCannotApplyIsOneRow) {
    conf::RunResult run = sample_run();
    conf::SuiteResult security{"security", "Security", "security.toml", {}};
    for (const char* id : {"sec.1", "sec.2", "sec.3"}) {
        security.cases.push_back(
            {id, "[SEC] R-01", "a case",
             conf::Outcome{conf::Verdict::NotApplicable, "not over mbaps://", {}}});
    }
    run.suites.push_back(security);
    const auto html = conform_html_report(run, sample_provenance());
    EXPECT_TRUE(has(html,
                    "<tbody class=\"case\" data-verdict=\"N/A\" data-id=\"sec.1 sec.2 "
                    "sec.3\">\n<tr><td>all 3</td><td class=\"NA\">N/A</td><td>all 3 cases "
                    "of security</td><td>not over mbaps://</td>"))
        << html;
    EXPECT_FALSE(has(html, "<td>sec.2</td>"));
}

TEST(ConformHtml, SaysTheRunWasInterrupted) {
    auto run = sample_run();
    run.interrupted = true;
    run.suites[0].cases[3].interrupted = true;
    const auto html = conform_html_report(run, sample_provenance());
    EXPECT_TRUE(has(html, "INTERRUPTED: the run was interrupted after 3 of 4 cases"));
}

// Nothing is fetched: no src or href names another place, so the file works from file://.
TEST(ConformHtml, IsSelfContained) {
    const auto html = conform_html_report(sample_run(), sample_provenance());
    // Nothing is loaded from elsewhere. The only links are the source column's, to the cited
    // documents, followed only when clicked.
    EXPECT_FALSE(std::regex_search(html, std::regex(R"(src\s*=)")));
    EXPECT_FALSE(has(html, "<link"));
    EXPECT_FALSE(has(html, "url("));
    EXPECT_FALSE(has(html, "http://"));
    const auto count = [&html](const std::regex& pattern) {
        return std::distance(std::sregex_iterator(html.begin(), html.end(), pattern),
                             std::sregex_iterator());
    };
    EXPECT_EQ(count(std::regex(R"(href\s*=)")), count(std::regex(R"(<a href="https://)")));
    EXPECT_EQ(count(std::regex(R"(<a href="https://)")), 4);
    EXPECT_TRUE(has(html, "<style>"));
    EXPECT_TRUE(has(html, "<script>"));
}

load::LatencySnapshot latencies() {
    load::LatencyHistogram histogram;
    for (std::uint64_t micros : {50, 60, 60, 200, 210, 5000})
        histogram.record(micros);
    load::LatencySnapshot snapshot;
    histogram.snapshot_into(snapshot);
    return snapshot;
}

TEST(LoadHtml, DrawsTheLatencyHistogramAsBars) {
    const auto svg = latency_svg(latencies(), 4);
    EXPECT_TRUE(svg.starts_with("<svg class=\"histogram\""));
    std::size_t bars = 0;
    std::uint64_t answers = 0;
    const std::regex bar(R"(<rect class="bar"[^>]*><title>[0-9.]+-[0-9.]+ ms: (\d+) answers)");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator();
         ++it) {
        ++bars;
        answers += std::stoull((*it)[1]);
    }
    EXPECT_EQ(bars, 4U);
    EXPECT_EQ(answers, 6U);
    // Both axes are named; the latency axis has ticks from the first bar's lower edge to the
    // last bar's upper one.
    EXPECT_TRUE(has(svg, ">answers</text>"));
    EXPECT_TRUE(has(svg, ">latency (ms)</text>"));
    EXPECT_TRUE(has(svg, ">0.050</text>"));
    EXPECT_TRUE(has(svg, ">5.000</text>"));
    EXPECT_TRUE(has(latency_svg(load::LatencySnapshot{}), "no answers"));
}

TEST(LoadHtml, HasANodeTableAHistogramPerNodeAndTheFailure) {
    load::LoadPlan plan;
    plan.settings.duration = std::chrono::seconds(2);
    plan.settings.connections = 0;
    load::LoadResult result;
    result.elapsed = std::chrono::seconds(2);
    load::NodeResult good;
    good.target = "tcp://127.0.0.1:1502";
    good.sent = good.answered = 6;
    good.latency = latencies();
    load::NodeResult bad;
    bad.target = "tcp://127.0.0.1:<&>";
    bad.sent = 3;
    bad.answered = 2;
    bad.failures[static_cast<std::size_t>(load::FailureKind::WrongAnswer)] = 1;
    bad.first_failure =
        load::FailureRecord{load::FailureKind::WrongAnswer, std::chrono::microseconds(1000),
                            "7.3.1", "wrong transaction id", failed_read()};
    result.nodes = {good, bad};
    const auto html = load_html_report(plan, result);
    EXPECT_TRUE(has(html, "<table id=\"nodes\">"));
    EXPECT_TRUE(has(html, "<tr class=\"node\"><td>tcp://127.0.0.1:1502</td>"));
    EXPECT_TRUE(has(html, "<tr class=\"node\"><td>tcp://127.0.0.1:&lt;&amp;&gt;</td>"));
    // A column for the one kind of failure seen, none for the kinds nobody counted, so the
    // latency columns stay on screen.
    EXPECT_TRUE(has(html, "<th>failures</th><th>wrong_answer</th><th>p50 ms</th>")) << html;
    EXPECT_FALSE(has(html, "<th>timeout</th>"));
    std::size_t charts = 0;
    for (auto at = html.find("<svg class=\"histogram\""); at != std::string::npos;
         at = html.find("<svg class=\"histogram\"", at + 1))
        ++charts;
    EXPECT_EQ(charts, 2U);
    EXPECT_TRUE(has(html, "data-verdict=\"FAIL\" data-id=\"tcp://127.0.0.1:&lt;&amp;&gt;\""));
    EXPECT_TRUE(has(html, "received  00 <mark class=\"diff\">01</mark>"));
    EXPECT_TRUE(has(html, "<p class=\"banner FAIL\" id=\"outcome\">FAIL</p>"));
    EXPECT_FALSE(has(html, "http://"));
}

}  // namespace
}  // namespace mblab::web
