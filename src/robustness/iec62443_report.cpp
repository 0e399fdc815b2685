#include "robustness/iec62443_report.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "support/comma_list.hpp"

namespace mblab::robustness {

namespace {

// The console names this many of the cases that lost cycles.
constexpr std::size_t kCasesShown = 10;

double as_ms(std::chrono::microseconds span) {
    return static_cast<double>(span.count()) / 1000.0;
}

}  // namespace

std::string requirement_of(BadInput kind) {
    switch (kind) {
        case BadInput::ManyConnections:
        case BadInput::SlowReader:
        case BadInput::HalfOpen:
        case BadInput::PartialHeader:
            return "CR 7.1 denial-of-service protection; CR 7.2 resource management";
        case BadInput::Flood:
        case BadInput::Pipelined:
            return "CR 7.1 denial-of-service protection; CR 3.6 deterministic output";
        default:
            return "CR 3.5 input validation";
    }
}

protocol::Result<MonitorSpec, std::string> parse_monitor_spec(const std::string& text,
                                                              MonitorSpec spec) {
    for (const auto& item : comma_items(text)) {
        if (item == "read-only") {
            spec.read_only = true;
            continue;
        }
        const auto equals = item.find('=');
        const auto key = item.substr(0, equals);
        const auto value = equals == std::string::npos ? std::string() : item.substr(equals + 1);
        unsigned long number = 0;
        try {
            std::size_t used = 0;
            number = std::stoul(value, &used, 0);
            if (used != value.size()) throw std::invalid_argument(value);
        } catch (const std::exception&) {
            return fmt::format(
                "--monitor '{}': '{}' is not KEY=NUMBER (keys: register, period, budget, miss; or "
                "read-only)",
                text, item);
        }
        if (key == "register" && number <= 0xFFFF) {
            spec.address = static_cast<std::uint16_t>(number);
        } else if (key == "period" && number >= 10 && number <= 600000) {
            spec.period = std::chrono::milliseconds(number);
        } else if (key == "budget" && number >= 1 && number <= 600000) {
            spec.budget = std::chrono::milliseconds(number);
        } else if (key == "miss" && number <= 100) {
            spec.miss_percent = static_cast<double>(number);
        } else {
            return fmt::format(
                "--monitor '{}': '{}' is out of range or unknown (register 0-65535, period "
                "10-600000 "
                "ms, budget 1-600000 ms, miss 0-100 %)",
                text, item);
        }
    }
    if (spec.budget > spec.period)
        return fmt::format("--monitor '{}': the budget ({} ms) is longer than the period ({} ms)",
                           text, spec.budget.count(), spec.period.count());
    return spec;
}

std::string monitor_text(const MonitorJudgement& judged, const MonitorSpec& spec) {
    std::string out = fmt::format(
        "essential-function monitor: {} register {} every {} ms, budget {} ms, {}% missed "
        "tolerated\n",
        spec.read_only ? "FC 03 of" : "FC 06 then FC 03 read-back of", spec.address,
        spec.period.count(), spec.budget.count(), spec.miss_percent);
    // The names in a column: the storms' are longer than the fixed phases'.
    std::size_t width = 16;
    for (const auto& p : judged.phases)
        width = std::max(width, p.phase.name.size());
    for (const auto& p : judged.phases) {
        out += fmt::format(
            "  {:<{}} {:>5} cycles, {:>4} missed ({:.1f}%), median {:.2f} ms, worst {:.2f} ms: "
            "{} [{}]\n",
            p.phase.name, width, p.cycles, p.missed, p.missed_percent, as_ms(p.median),
            as_ms(p.worst), p.held ? "held" : "lost", p.phase.requirement);
    }
    if (!judged.missed_during.empty())
        out += fmt::format("  cycles missed during {} case(s):\n", judged.missed_during.size());
    for (std::size_t i = 0; i < judged.missed_during.size() && i < kCasesShown; ++i)
        out += fmt::format("    {}\n", missed_during_text(judged.missed_during[i]));
    if (judged.missed_during.size() > kCasesShown)
        out += fmt::format("    and {} more (the JSON report and monitor.html name them all)\n",
                           judged.missed_during.size() - kCasesShown);
    if (judged.recovery) {
        out += fmt::format("  back within budget {} ms into the recovery phase\n",
                           judged.recovery->count());
    }
    out += fmt::format("MONITOR VERDICT: {}: {}\n", verdict_name(judged.verdict), judged.why);
    out += fmt::format("out of scope: {}\n", kOutOfScope);
    return out;
}

nlohmann::json monitor_json(const MonitorJudgement& judged, const MonitorSpec& spec,
                            const std::vector<MonitorCycle>& cycles) {
    nlohmann::json phases = nlohmann::json::array();
    for (const auto& p : judged.phases) {
        phases.push_back({{"phase", p.phase.name},
                          {"requirement", p.phase.requirement},
                          {"cycles", p.cycles},
                          {"missed", p.missed},
                          {"missed_percent", p.missed_percent},
                          {"held", p.held},
                          {"median_us", p.median.count()},
                          {"worst_us", p.worst.count()}});
    }
    nlohmann::json samples = nlohmann::json::array();
    const auto origin = cycles.empty() ? Clock::time_point{} : cycles.front().started;
    for (const auto& c : cycles) {
        if (c.pending()) continue;
        const auto at =
            std::chrono::duration_cast<std::chrono::milliseconds>(c.started - origin).count();
        if (c.held()) {
            samples.push_back({{"at_ms", at}, {"latency_us", c.latency->count()}});
        } else {
            samples.push_back({{"at_ms", at}, {"missed", c.missed}});
        }
    }
    nlohmann::json during = nlohmann::json::array();
    for (const auto& d : judged.missed_during) {
        during.push_back({{"case", d.case_number},
                          {"class", class_name(d.kind)},
                          {"name", d.case_name},
                          {"missed", d.missed},
                          {"reason", d.reason}});
    }
    nlohmann::json out = {
        {"register", spec.address},
        {"period_ms", spec.period.count()},
        {"budget_ms", spec.budget.count()},
        {"miss_percent_tolerated", spec.miss_percent},
        {"read_only", spec.read_only},
        {"phases", phases},
        {"longest_outage_ms", judged.longest_outage.count()},
        {"verdict", verdict_name(judged.verdict)},
        {"why", judged.why},
        {"out_of_scope", kOutOfScope},
        {"cycles", samples},
        {"missed_during", during},
    };
    out["recovery_ms"] = judged.recovery ? nlohmann::json(judged.recovery->count()) : nullptr;
    return out;
}

}  // namespace mblab::robustness
