// /metrics of serve and load, read back by a strict Prometheus text-format reader.
#include <gtest/gtest.h>

#include "load/runner.hpp"
#include "prometheus_parser.hpp"
#include "web/load_metrics.hpp"
#include "web/metrics_text.hpp"
#include "web/serve_metrics.hpp"
#include "web_harness.hpp"

namespace mblab::test {
namespace {

const PromFamily* find(const std::vector<PromFamily>& families, const std::string& name) {
    for (const auto& family : families) {
        if (family.name == name) return &family;
    }
    return nullptr;
}

double value_of(const PromFamily* family, const std::string& name,
                const std::map<std::string, std::string>& labels) {
    if (!family) return -1;
    for (const auto& sample : family->samples) {
        if (sample.name == name && sample.labels == labels) return sample.value;
    }
    return -1;
}

TEST(MetricsText, LabelValuesAreEscaped) {
    web::MetricsText text;
    text.family("x_total", "counter", "Help.");
    text.sample("x_total", {{"target", "a\"b\\c\nd"}}, 3);
    EXPECT_EQ(text.text(),
              "# HELP x_total Help.\n# TYPE x_total counter\n"
              "x_total{target=\"a\\\"b\\\\c\\nd\"} 3\n");
    std::string error;
    auto families = parse_prometheus(text.text(), error);
    ASSERT_EQ(families.size(), 1U) << error;
    EXPECT_EQ(families[0].samples[0].labels.at("target"), "a\"b\\c\nd");
}

TEST(MetricsText, TheReaderRefusesWhatAScraperWould) {
    std::string error;
    EXPECT_TRUE(parse_prometheus("x 1\n", error).empty());  // no TYPE
    EXPECT_TRUE(parse_prometheus("# HELP x h\n# TYPE x counter\nx -1\n", error).empty());
    EXPECT_TRUE(parse_prometheus("# HELP x h\n# TYPE x histogram\nx_bucket{le=\"1\"} 2\n"
                                 "x_bucket{le=\"+Inf\"} 1\nx_count 1\nx_sum 0\n",
                                 error)
                    .empty());
    EXPECT_EQ(error, "x: buckets not cumulative in ascending le");
}

TEST(ServeMetrics, CountsRequestsExceptionsAndAnswerTimes) {
    WebHarness h;
    h.ask("03 00 00 00 01");
    h.ask("03 00 00 00 01");
    h.ask("06 00 00 00 01");  // answered 86 06 by the profile's fault rule
    h.ask("2B 0E 01 00", 2);
    std::string error;
    const auto families = parse_prometheus(web::serve_metrics(h.api().view()), error);
    ASSERT_FALSE(families.empty()) << error;
    const auto* requests = find(families, "mblab_requests_total");
    EXPECT_EQ(value_of(requests, "mblab_requests_total", {{"unit", "1"}, {"function", "0x03"}}), 2);
    EXPECT_EQ(value_of(requests, "mblab_requests_total", {{"unit", "2"}, {"function", "0x2B"}}), 1);
    const auto* exceptions = find(families, "mblab_exceptions_total");
    EXPECT_EQ(value_of(exceptions, "mblab_exceptions_total", {{"unit", "1"}, {"function", "0x06"}}),
              1);
    EXPECT_EQ(value_of(exceptions, "mblab_exceptions_total", {{"unit", "1"}, {"function", "0x03"}}),
              0);
    const auto* latency = find(families, "mblab_request_duration_seconds");
    ASSERT_NE(latency, nullptr);
    EXPECT_EQ(latency->type, "histogram");
    EXPECT_EQ(value_of(latency, "mblab_request_duration_seconds_count", {}), 4);
    EXPECT_EQ(value_of(find(families, "mblab_connections"), "mblab_connections", {}), 3);
    EXPECT_EQ(value_of(find(families, "mblab_line_errors"), "mblab_line_errors", {{"unit", "1"}}),
              0);
    // Every unit on the bus sees every message, unit 2's too.
    EXPECT_EQ(value_of(find(families, "mblab_bus_messages"), "mblab_bus_messages", {{"unit", "1"}}),
              4);
}

TEST(ServeMetrics, AFaultDelayCountsInTheAnswerTime) {
    WebHarness h;
    h.call("POST", "/api/units/1/faults", R"({"action":"delay","delay_ms":300,"functions":[3]})");
    h.ask("03 00 00 00 01");
    std::string error;
    const auto families = parse_prometheus(web::serve_metrics(h.api().view()), error);
    const auto* latency = find(families, "mblab_request_duration_seconds");
    EXPECT_EQ(value_of(latency, "mblab_request_duration_seconds_bucket", {{"le", "0.25"}}), 0);
    EXPECT_EQ(value_of(latency, "mblab_request_duration_seconds_bucket", {{"le", "0.5"}}), 1);
}

TEST(LoadMetrics, PerNodeCountersAndACumulativeHistogram) {
    load::LoadPlan plan;
    plan.targets.resize(2);
    plan.targets[0].url = "tcp://127.0.0.1:1502";
    plan.targets[1].url = "tcp://127.0.0.1:1503";
    load::LoadStatus status;
    status.elapsed = std::chrono::milliseconds(1500);
    status.nodes.resize(2);
    status.nodes[0].sent = 10;
    status.nodes[0].answered = 9;
    status.nodes[0].failures = 1;
    load::LatencyHistogram histogram;
    for (std::uint64_t micros : {40, 90, 300, 300, 2000, 20000000})
        histogram.record(micros);
    histogram.snapshot_into(status.nodes[0].latency);
    std::string error;
    const auto families = parse_prometheus(web::load_metrics(plan, status), error);
    ASSERT_FALSE(families.empty()) << error;
    const std::map<std::string, std::string> first{{"target", "tcp://127.0.0.1:1502"}};
    EXPECT_EQ(
        value_of(find(families, "mblab_load_answers_total"), "mblab_load_answers_total", first), 9);
    EXPECT_EQ(
        value_of(find(families, "mblab_load_failures_total"), "mblab_load_failures_total", first),
        1);
    const auto* latency = find(families, "mblab_load_answer_duration_seconds");
    const auto bucket = [&](const std::string& le) {
        auto labels = first;
        labels["le"] = le;
        return value_of(latency, "mblab_load_answer_duration_seconds_bucket", labels);
    };
    EXPECT_EQ(bucket("5e-05"), 1);
    EXPECT_EQ(bucket("0.0001"), 2);
    EXPECT_EQ(bucket("0.0005"), 4);
    EXPECT_EQ(bucket("0.0025"), 5);
    EXPECT_EQ(bucket("10"), 5);
    EXPECT_EQ(bucket("+Inf"), 6);
    EXPECT_EQ(
        value_of(find(families, "mblab_load_elapsed_seconds"), "mblab_load_elapsed_seconds", {}),
        1.5);
}

}  // namespace
}  // namespace mblab::test
