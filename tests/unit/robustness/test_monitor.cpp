// The essential-function monitor as traces: what it sends, what the device answers and when, on a
// manual clock; then its cycles judged PASS, DEGRADED or FAIL.
#include <gtest/gtest.h>

#include "robustness/iec62443_report.hpp"
#include "robustness/ladder_report.hpp"
#include "robustness/monitor_core.hpp"
#include "robustness/monitor_html.hpp"
#include "robustness/monitor_junit.hpp"
#include "robustness/monitor_verdict.hpp"
#include "support/hex.hpp"
#include "support/manual_clock.hpp"

namespace mblab::robustness {
namespace {

using namespace std::chrono_literals;
using test::hex;
using test::to_hex;

MonitorSpec every_100ms() {
    MonitorSpec spec;
    spec.address = 7;
    spec.period = 100ms;
    spec.budget = 50ms;
    return spec;
}

struct Trace {
    explicit Trace(MonitorSpec spec = every_100ms()) : core(spec, clock.now()) {}
    std::string sends() { return to_hex(core.poll(clock.now())); }
    void answers(const char* text, std::chrono::milliseconds after) {
        clock.advance(after);
        core.received(hex(text), clock.now());
    }
    test::ManualClock clock;
    MonitorCore core;
};

TEST(MonitorCore, WritesAChangingValueThenReadsItBack) {
    Trace t;
    EXPECT_EQ(t.sends(), "00 01 00 00 00 06 01 06 00 07 00 01");
    EXPECT_EQ(t.sends(), "");  // the write is still out
    t.answers("00 01 00 00 00 06 01 06 00 07 00 01", 3ms);
    EXPECT_EQ(t.core.deadline(), t.core.cycles().back().started);  // the read is due now
    EXPECT_EQ(t.sends(), "00 02 00 00 00 06 01 03 00 07 00 01");
    t.answers("00 02 00 00 00 05 01 03 02 00 01", 2ms);
    ASSERT_EQ(t.core.cycles().size(), 1U);
    EXPECT_TRUE(t.core.cycles()[0].held());
    EXPECT_EQ(t.core.cycles()[0].latency, 5000us);
    // The next cycle on its period, with the next value.
    EXPECT_EQ(t.core.deadline(), t.core.cycles()[0].started + 100ms);
    t.clock.advance(95ms);
    EXPECT_EQ(t.sends(), "00 03 00 00 00 06 01 06 00 07 00 02");
}

TEST(MonitorCore, ARegisterThatStopsUpdatingIsAMiss) {
    Trace t;
    t.sends();
    t.answers("00 01 00 00 00 06 01 06 00 07 00 01", 1ms);
    t.sends();
    // The write was acknowledged, yet the register reads its old value.
    t.answers("00 02 00 00 00 05 01 03 02 00 00", 1ms);
    EXPECT_EQ(t.core.cycles()[0].missed, "read 0 after writing 1");
}

TEST(MonitorCore, NoAnswerWithinTheBudgetIsAMissAndALateAnswerIsIgnored) {
    Trace t;
    t.sends();
    t.clock.advance(50ms);
    EXPECT_EQ(t.sends(), "");
    EXPECT_EQ(t.core.cycles()[0].missed, "no answer within 50 ms");
    // The late echo of the missed cycle's write does not count for the next one.
    t.clock.advance(50ms);
    EXPECT_EQ(t.sends(), "00 02 00 00 00 06 01 06 00 07 00 02");
    t.answers("00 01 00 00 00 06 01 06 00 07 00 01", 1ms);
    EXPECT_EQ(t.sends(), "");
    t.answers("00 02 00 00 00 06 01 06 00 07 00 02", 1ms);
    EXPECT_EQ(t.sends(), "00 03 00 00 00 06 01 03 00 07 00 01");
}

TEST(MonitorCore, AnExceptionOrALostConnectionIsAMiss) {
    Trace t;
    t.sends();
    t.answers("00 01 00 00 00 03 01 86 04", 1ms);
    EXPECT_EQ(t.core.cycles()[0].missed, "FC 06 answered exception 04");
    t.clock.advance(99ms);
    t.sends();
    t.core.connection_lost(t.clock.now());
    EXPECT_EQ(t.core.cycles()[1].missed, "the connection closed");
}

TEST(MonitorCore, TheDeviceIsJudgedOnItsOwnTimeNotTheTesters) {
    Trace t;
    t.sends();
    t.answers("00 01 00 00 00 06 01 06 00 07 00 01", 10ms);
    // The tester's thread sends the read-back 60 ms after the echo (starved of CPU): not the
    // device's time, so the budget is not spent and the read is still awaited.
    t.clock.advance(60ms);
    EXPECT_EQ(t.sends(), "00 02 00 00 00 06 01 03 00 07 00 01");
    EXPECT_EQ(t.core.deadline(), t.clock.now() + 40ms);
    t.answers("00 02 00 00 00 05 01 03 02 00 01", 5ms);
    EXPECT_EQ(t.core.cycles()[0].latency, 15000us);

    // An answer that arrived over the budget holds not, even when read before poll() judged it.
    t.clock.advance(25ms);
    t.sends();
    t.answers("00 03 00 00 00 06 01 06 00 07 00 02", 30ms);
    t.sends();
    t.answers("00 04 00 00 00 05 01 03 02 00 02", 25ms);
    EXPECT_EQ(t.core.cycles()[1].missed, "answered in 55.0 ms, over the 50 ms budget");
}

TEST(MonitorCore, ReadOnlyJudgesTheReadAlone) {
    MonitorSpec spec = every_100ms();
    spec.read_only = true;
    Trace t(spec);
    EXPECT_EQ(t.sends(), "00 01 00 00 00 06 01 03 00 07 00 01");
    t.answers("00 01 00 00 00 05 01 03 02 12 34", 4ms);
    EXPECT_TRUE(t.core.cycles()[0].held());
}

// Cycles every 100 ms from `start`; `missed` says which miss.
std::vector<MonitorCycle> cycles_from(Clock::time_point start, const std::string& pattern) {
    std::vector<MonitorCycle> out;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        MonitorCycle c{start + i * 100ms, std::nullopt, {}};
        if (pattern[i] == 'x') {
            c.missed = "no answer within 50 ms";
        } else {
            c.latency = 2000us;
        }
        out.push_back(c);
    }
    return out;
}

std::vector<MonitorPhase> three_phases(Clock::time_point start) {
    return {{"baseline", "CR 7.1", start, start + 500ms},
            {"malformed input", "CR 3.5", start + 500ms, start + 1500ms},
            {"recovery", "CR 7.1", start + 1500ms, start + 2000ms}};
}

TEST(MonitorVerdict, PassDegradedAndFail) {
    const auto start = test::ManualClock().now();
    const auto spec = every_100ms();
    const auto phases = three_phases(start);
    auto judged = judge_monitor(cycles_from(start, "....................."), spec, phases, 500ms);
    EXPECT_EQ(judged.verdict, MonitorVerdict::Pass) << judged.why;
    EXPECT_EQ(judged.phases[1].median, 2000us);
    EXPECT_EQ(judged.recovery, 2ms);

    // Lost for 300 ms in the malformed phase, back by itself: degraded within a 500 ms limit.
    judged = judge_monitor(cycles_from(start, ".......xxx..........."), spec, phases, 500ms);
    EXPECT_EQ(judged.verdict, MonitorVerdict::Degraded) << judged.why;
    EXPECT_EQ(judged.longest_outage, 300ms);
    EXPECT_EQ(judged.phases[1].missed, 3U);
    EXPECT_FALSE(judged.phases[1].held);
    EXPECT_TRUE(judged.phases[2].held);
    // The same outage over a 200 ms limit fails.
    EXPECT_EQ(
        judge_monitor(cycles_from(start, ".......xxx..........."), spec, phases, 200ms).verdict,
        MonitorVerdict::Fail);

    // Never back: fails, however long the limit.
    judged = judge_monitor(cycles_from(start, "..........xxxxxxxxxx"), spec, phases, 60000ms);
    EXPECT_EQ(judged.verdict, MonitorVerdict::Fail);
    EXPECT_EQ(judged.why, "the monitor did not come back without a restart");
    EXPECT_FALSE(judged.recovery);

    // The cycle under way when the monitor stopped is neither: a device that never came back
    // is not taken for one that did.
    auto unfinished = cycles_from(start, "..........xxxxxxxxx");
    unfinished.push_back({start + 1900ms, std::nullopt, {}});
    EXPECT_EQ(judge_monitor(unfinished, spec, phases, 60000ms).verdict, MonitorVerdict::Fail);

    // Misses within the tolerated percent hold.
    MonitorSpec tolerant = spec;
    tolerant.miss_percent = 20;
    EXPECT_EQ(
        judge_monitor(cycles_from(start, "........x............"), tolerant, phases, 0ms).verdict,
        MonitorVerdict::Pass);
}

TEST(MonitorSpec, ParsedOverTheDefaults) {
    MonitorSpec defaults;
    defaults.address = 3;
    const auto spec = parse_monitor_spec("period=200,miss=5", defaults);
    ASSERT_TRUE(spec) << spec.error();
    EXPECT_EQ(spec->address, 3);
    EXPECT_EQ(spec->period, 200ms);
    EXPECT_EQ(spec->budget, 50ms);
    EXPECT_EQ(spec->miss_percent, 5);
    const auto read_only = parse_monitor_spec("register=0x10,read-only,budget=20", defaults);
    ASSERT_TRUE(read_only) << read_only.error();
    EXPECT_EQ(read_only->address, 16);
    EXPECT_TRUE(read_only->read_only);
    EXPECT_FALSE(parse_monitor_spec("register=70000", defaults));
    EXPECT_FALSE(parse_monitor_spec("speed=3", defaults));
    EXPECT_FALSE(parse_monitor_spec("budget=500", defaults));  // longer than the period
}

TEST(MonitorReport, PhasesAndFindingsNameTheirRequirement) {
    EXPECT_EQ(requirement_of(BadInput::Quantity), "CR 3.5 input validation");
    EXPECT_EQ(requirement_of(BadInput::SlowReader),
              "CR 7.1 denial-of-service protection; CR 7.2 resource management");
    const auto start = test::ManualClock().now();
    const auto judged = judge_monitor(cycles_from(start, ".......xxx..........."), every_100ms(),
                                      three_phases(start), 500ms);
    const auto text = monitor_text(judged, every_100ms());
    EXPECT_NE(text.find("  malformed input     10 cycles,    3 missed (30.0%), median 2.00 ms, "
                        "worst 2.00 ms: lost [CR 3.5]\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("MONITOR VERDICT: DEGRADED: "), std::string::npos) << text;
    EXPECT_NE(text.find("out of scope: Ethernet, ARP, IP and ICMP storms"), std::string::npos);
    const auto json = monitor_json(judged, every_100ms(), cycles_from(start, "..x"));
    EXPECT_EQ(json["verdict"], "DEGRADED");
    EXPECT_EQ(json["cycles"][2]["at_ms"], 200);
    EXPECT_EQ(json["cycles"][2]["missed"], "no answer within 50 ms");
    EXPECT_EQ(json["cycles"][0]["latency_us"], 2000);
}

// Two storms: FC 03 held at 100/s and was lost at 1000/s (cycles 5-9); opens held at both rungs.
TEST(StormLadder, EachStormsHighestRateHeldAndWhereItWasLost) {
    const auto start = test::ManualClock().now();
    const std::vector<MonitorPhase> phases = {
        {"storm 100/s", "CR 7.1", start, start + 500ms},
        {"storm 1000/s", "CR 7.1", start + 500ms, start + 1000ms},
        {"storm opens 10/s", "CR 7.1", start + 1000ms, start + 1500ms},
        {"storm opens 50/s", "CR 7.1", start + 1500ms, start + 2000ms},
        {"recovery", "CR 7.1", start + 2000ms, start + 2500ms}};
    const auto judged = judge_monitor(cycles_from(start, ".....xxxx................"),
                                      every_100ms(), phases, 1000ms);
    std::vector<LadderRung> rungs = {{100, start, start + 500ms, 50, 50, 0},
                                     {1000, start + 500ms, start + 1000ms, 500, 20, 1},
                                     {10, start + 1000ms, start + 1500ms, 0, 0, 0},
                                     {50, start + 1500ms, start + 2000ms, 0, 0, 0}};
    for (auto& rung : {&rungs[2], &rungs[3]}) {
        rung->kind = StormKind::Opens;
        rung->opened = static_cast<std::size_t>(rung->rate / 2) - 1;
        rung->refused = 1;
    }
    const std::vector<StormNotRun> not_run = {{StormKind::Fc06, "no holding register"},
                                              {StormKind::HalfOpen, "no CAP_NET_ADMIN"}};
    const auto text = ladder_text(judged, rungs, not_run);
    EXPECT_NE(text.find("storm ladder (FC 03 (read holding registers) of the monitor's register, "
                        "answers never waited for):\n       100/s asked,      100/s sent,      "
                        "100/s answered, 0 "
                        "reconnect(s): the monitor held\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("1000/s sent,       40/s answered, 1 reconnect(s): the monitor was lost"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("the monitor held up to 100 requests/s, lost at 1000/s [CR 7.1]\n"
                        "storm ladder (connections opened and closed at once):\n"
                        "        10/s asked,        8/s opened, 1 refused: the monitor held\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("the monitor held up to 50 connection opens/s [CR 7.1]\n"
                        "storm ladder (connections sending 3 bytes of a request, then gone "
                        "without a FIN): not run: no CAP_NET_ADMIN\n"
                        "requests per second per function code [CR 7.1]:\n"
                        "  FC 03 read holding registers           held up to 100 requests/s, "
                        "lost at 1000/s\n"
                        "  FC 06 write single register            not run: no holding register\n"),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("FC 01"), std::string::npos) << text;  // not asked for, not listed
    const auto suite = monitor_junit_suite(judged, rungs, not_run);
    EXPECT_EQ(suite.skipped, 2U);
    for (const char* part :
         {"<testcase classname=\"monitor.ladder\" name=\"fc03\" time=\"0\">\n      <failure "
          "message=\"held up to 100 requests/s, lost at 1000/s [CR 7.1]\" type=\"monitor "
          "lost\">storm 1000/s: 4 of 5 cycles missed (80.0%)\nCR 7.1</failure>",
          "name=\"opens\" time=\"0\">\n      <system-out>held up to 50 connection opens/s "
          "[CR 7.1]</system-out>",
          "name=\"fc06\" time=\"0\">\n      <skipped message=\"not run: no holding "
          "register\"/>"}) {
        EXPECT_NE(suite.xml.find(part), std::string::npos) << part << "\n" << suite.xml;
    }
    EXPECT_NE(suite.xml.find("skipped=\"2\""), std::string::npos);
    // A rung is judged in its storm's case: the loss at 1000/s is one failure, not two.
    EXPECT_EQ(suite.xml.find("name=\"storm 1000/s\""), std::string::npos) << suite.xml;
    EXPECT_EQ(suite.xml.find("name=\"storm opens 10/s\""), std::string::npos) << suite.xml;
    EXPECT_NE(suite.xml.find("name=\"recovery\""), std::string::npos) << suite.xml;
    EXPECT_EQ(suite.failures, judged.verdict == MonitorVerdict::Pass ? 1U : 2U);
    const auto page = monitor_html(FuzzResult{}, judged, every_100ms(), {}, rungs, not_run);
    EXPECT_NE(page.find("<tr><td>FC 03 read holding registers</td><td>100/s</td><td>1000/s</td>"
                        "<td>CR 7.1</td></tr>\n<tr><td>FC 06 write single register</td><td "
                        "colspan=\"3\">not run: no holding register</td></tr>"),
              std::string::npos)
        << page;
    const auto json = ladder_json(judged, rungs, not_run);
    EXPECT_EQ(json["storms"][0]["function"], 3);
    EXPECT_EQ(json["storms"][0]["requirement"], "CR 7.1");
    EXPECT_FALSE(json["storms"][1].contains("function"));
    EXPECT_EQ(json["not_run"][0]["storm"], "fc06");
    EXPECT_EQ(json["not_run"][0]["function"], 6);
    EXPECT_EQ(json["not_run"][0]["reason"], "no holding register");
    EXPECT_EQ(json["storms"][0]["storm"], "fc03");
    EXPECT_EQ(json["storms"][0]["highest_rate_held"], 100.0);
    EXPECT_EQ(json["storms"][0]["lost_at"], 1000.0);
    EXPECT_EQ(json["storms"][1]["highest_rate_held"], 50.0);
    EXPECT_TRUE(json["storms"][1]["lost_at"].is_null());
    EXPECT_EQ(json["rungs"][3]["opened"], 24);
}

// The page: the chart with a point per cycle that held and a red mark per cycle missed, the
// verdict, the phases with their requirements, each finding with its reproducer.
TEST(MonitorHtml, TheChartThePhasesAndTheFindings) {
    const auto start = test::ManualClock().now();
    const auto cycles = cycles_from(start, ".......xxx...........");
    const auto judged = judge_monitor(cycles, every_100ms(), three_phases(start), 500ms);
    FuzzResult result;
    result.target = "tcp://127.0.0.1:1502";
    Finding finding;
    finding.kind = BadInput::SlowReader;
    finding.case_name = "40000 reads <unread>";
    finding.reason = "refuses connections";
    finding.reproducer = {Step(0, {0x00, 0x01})};
    result.findings.push_back(finding);
    const auto page = monitor_html(result, judged, every_100ms(), cycles, {});
    const auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (auto at = page.find(what); at != std::string::npos; at = page.find(what, at + 1))
            ++n;
        return n;
    };
    EXPECT_EQ(count("<svg "), 1U);
    EXPECT_EQ(count("fill=\"#d00\"><title>no answer within 50 ms</title>"), 3U);
    EXPECT_EQ(count("<polyline points="), 1U);
    EXPECT_NE(page.find("<strong>Verdict: DEGRADED</strong>"), std::string::npos);
    EXPECT_NE(page.find("<td>malformed input</td><td>10</td><td>3 (30.0%)</td>"),
              std::string::npos);
    EXPECT_NE(page.find("<h3>slow-reader: 40000 reads &lt;unread&gt; [CR 7.1 denial-of-service "
                        "protection; CR 7.2 resource management]</h3>"),
              std::string::npos)
        << page;
    EXPECT_NE(page.find("<pre>00 01\n</pre>"), std::string::npos) << page;
    EXPECT_NE(page.find("Out of scope: Ethernet, ARP, IP and ICMP storms"), std::string::npos);
}

TEST(MonitorJunit, APhaseThatLostTheMonitorAndTheVerdictFail) {
    const auto start = Clock::time_point{} + 1h;
    const auto judged = judge_monitor(cycles_from(start, ".....xx.........."), every_100ms(),
                                      three_phases(start), 10000ms);
    ASSERT_EQ(judged.verdict, MonitorVerdict::Degraded);
    const auto suite = monitor_junit_suite(judged);
    EXPECT_EQ(suite.tests, 4U);
    EXPECT_EQ(suite.failures, 2U);
    EXPECT_NE(suite.xml.find("<testcase classname=\"monitor\" name=\"baseline\" time=\"0.500\">"
                             "</testcase>"),
              std::string::npos);
    EXPECT_NE(suite.xml.find("name=\"malformed input\" time=\"1.000\">\n      <failure "
                             "message=\"2 of 10 cycles missed (20.0%)\" type=\"monitor lost\">"
                             "CR 3.5</failure>"),
              std::string::npos);
    EXPECT_NE(suite.xml.find("<failure message=\"DEGRADED: "), std::string::npos);
}

// Cycles every 100 ms, budget 50 ms; cases 1 (0-250 ms), 2 (250-260 ms), 3 (260-700 ms). The
// cycle missed at 200 ms (to 250) falls in case 1 alone; the one at 300 ms in case 3; the one at
// 900 ms after the last case (the recovery's) in none.
TEST(MonitorCases, EachMissedCycleLaidAgainstTheCasesThatRanMeanwhile) {
    const auto start = test::ManualClock().now();
    auto cycles = cycles_from(start, "..xx.....x");
    cycles[3].missed = "read 7 after writing 8";
    const std::vector<CaseSpan> cases = {
        {1, BadInput::Pipelined, "200 at once", start, start + 250ms},
        {2, BadInput::Quantity, "FC 0x03 quantity 0", start + 250ms, start + 260ms},
        {3, BadInput::SlowReader, "40000 reads", start + 260ms, start + 700ms}};
    const auto during = missed_during(cycles, cases, 50ms);
    ASSERT_EQ(during.size(), 2U);
    EXPECT_EQ(during[0].case_number, 1U);
    EXPECT_EQ(during[0].missed, 1U);
    EXPECT_EQ(missed_during_text(during[1]),
              "case 3 (slow-reader: 40000 reads): 1 cycle(s) missed, the first: read 7 after "
              "writing 8");
    // A cycle that spans several cases counts for each.
    const auto spanning = missed_during(cycles_from(start + 240ms, "x"), cases, 50ms);
    ASSERT_EQ(spanning.size(), 3U);
    EXPECT_EQ(missed_during(cycles, {}, 50ms).size(), 0U);
}

// The console, the JSON report, the page and the JUnit suite name the cases.
TEST(MonitorCases, EveryReportNamesThem) {
    const auto start = test::ManualClock().now();
    const auto cycles = cycles_from(start, ".......xxx...........");
    auto judged = judge_monitor(cycles, every_100ms(), three_phases(start), 500ms);
    judged.missed_during = missed_during(
        cycles, {{7, BadInput::Pipelined, "200 <at> once", start + 500ms, start + 1500ms}}, 50ms);
    const auto text = monitor_text(judged, every_100ms());
    EXPECT_NE(text.find("  cycles missed during 1 case(s):\n    case 7 (pipelined: 200 <at> "
                        "once): 3 cycle(s) missed, the first: no answer within 50 ms\n"),
              std::string::npos)
        << text;
    const auto json = monitor_json(judged, every_100ms(), cycles);
    EXPECT_EQ(json["missed_during"][0]["case"], 7);
    EXPECT_EQ(json["missed_during"][0]["class"], "pipelined");
    EXPECT_EQ(json["missed_during"][0]["missed"], 3);
    const auto page = monitor_html(FuzzResult{}, judged, every_100ms(), cycles, {});
    EXPECT_NE(page.find("<tr><td>7</td><td>pipelined</td><td>200 &lt;at&gt; once</td><td>3</td>"),
              std::string::npos)
        << page;
    const auto suite = monitor_junit_suite(judged);
    EXPECT_NE(suite.xml.find("CR 3.5\ncase 7 (pipelined: 200 &lt;at&gt; once): 3 cycle(s) "
                             "missed"),
              std::string::npos)
        << suite.xml;
}

}  // namespace
}  // namespace mblab::robustness
