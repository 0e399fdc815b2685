#include "web/load_metrics.hpp"

#include <chrono>

#include "web/metrics_text.hpp"

namespace mblab::web {

std::string load_metrics(const load::LoadPlan& plan, const load::LoadStatus& status) {
    MetricsText out;
    const auto nodes = std::min(plan.targets.size(), status.nodes.size());
    const auto each_node = [&](const char* name, const char* type, const char* help, auto value) {
        out.family(name, type, help);
        for (std::size_t i = 0; i < nodes; ++i) {
            out.sample(name, {{"target", plan.targets[i].url}},
                       static_cast<double>(value(status.nodes[i])));
        }
    };
    each_node("mblab_load_requests_total", "counter", "Requests sent to the node.",
              [](const load::NodeStatus& n) { return n.sent; });
    each_node("mblab_load_answers_total", "counter", "Answers received from the node.",
              [](const load::NodeStatus& n) { return n.answered; });
    each_node("mblab_load_failures_total", "counter",
              "Failures counted for the node (timeouts, wrong answers, closed connections).",
              [](const load::NodeStatus& n) { return n.failures; });
    each_node("mblab_load_answers_per_second", "gauge",
              "Answers per second over the last status period.",
              [](const load::NodeStatus& n) { return n.rate; });
    out.family("mblab_load_answer_duration_seconds", "histogram",
               "Time from a request to its answer.");
    const auto bounds = latency_bounds_seconds();
    for (std::size_t i = 0; i < nodes; ++i) {
        const auto& latency = status.nodes[i].latency;
        std::vector<std::uint64_t> cumulative;
        for (double bound : bounds) {
            cumulative.push_back(
                latency.count_at_most(static_cast<std::uint64_t>(bound * 1e6 + 0.5)));
        }
        out.histogram("mblab_load_answer_duration_seconds", {{"target", plan.targets[i].url}},
                      cumulative, latency.count(),
                      static_cast<double>(latency.approximate_sum()) / 1e6);
    }
    out.family("mblab_load_elapsed_seconds", "gauge", "Time since the run started.");
    out.sample("mblab_load_elapsed_seconds", {},
               std::chrono::duration<double>(status.elapsed).count());
    return out.text();
}

}  // namespace mblab::web
