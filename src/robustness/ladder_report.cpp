#include "robustness/ladder_report.hpp"

#include <fmt/core.h>

#include <optional>

#include "protocol/function_table.hpp"

namespace mblab::robustness {

namespace {

// Whether the monitor held in the rung's phase.
bool held_at(const MonitorJudgement& judged, const LadderRung& rung) {
    const auto name = storm_phase_name(rung.kind, rung.rate);
    for (const auto& p : judged.phases) {
        if (p.phase.name == name) return p.held;
    }
    return false;
}

std::string rung_line(const LadderRung& rung) {
    const auto seconds =
        std::max(1e-3, std::chrono::duration<double>(rung.end - rung.begin).count());
    const auto per_second = [&](std::size_t n) { return static_cast<double>(n) / seconds; };
    if (is_request_storm(rung.kind))
        return fmt::format("{:>8.0f}/s sent, {:>8.0f}/s answered, {} reconnect(s)",
                           per_second(rung.sent), per_second(rung.answered), rung.reconnects);
    switch (rung.kind) {
        case StormKind::Opens:
            return fmt::format("{:>8.0f}/s opened, {} refused", per_second(rung.opened),
                               rung.refused);
        case StormKind::SlowReaders:
            return fmt::format("{} held unread with {} requests written, {} refused", rung.opened,
                               rung.sent, rung.refused);
        case StormKind::HalfOpen:
            return fmt::format("{} left half-open, {} refused", rung.opened, rung.refused);
        default:
            break;
    }
    return {};
}

// Whether a storm holds the tester's or the device's resources past its requests: slow readers
// and half-open connections speak to resource management too.
bool holds_resources(StormKind kind) {
    return kind == StormKind::SlowReaders || kind == StormKind::HalfOpen;
}

// The request storms per function code: each one's summary or why it did not run, in the order
// of the codes.
std::string per_function_text(const std::vector<StormSummary>& all,
                              const std::vector<StormNotRun>& not_run) {
    std::string out;
    for (const auto kind : request_storms()) {
        const auto function = storm_words(kind).function;
        const auto name =
            fmt::format("FC {:02X} {}", function, protocol::find_function(function)->name);
        for (const auto& s : all) {
            if (s.kind == kind) out += fmt::format("  {:<38} {}\n", name, summary_words(s));
        }
        for (const auto& n : not_run) {
            if (n.kind == kind) out += fmt::format("  {:<38} not run: {}\n", name, n.reason);
        }
    }
    if (out.empty()) return out;
    return fmt::format("requests per second per function code [{}]:\n{}",
                       storm_tag(StormKind::Fc03), out);
}

}  // namespace

std::vector<StormSummary> storm_summaries(const MonitorJudgement& judged,
                                          const std::vector<LadderRung>& rungs) {
    std::vector<StormSummary> out;
    for (const auto& rung : rungs) {
        if (out.empty() || out.back().kind != rung.kind) out.push_back({rung.kind, {}, {}});
        auto& summary = out.back();
        if (summary.lost_at) continue;
        if (held_at(judged, rung)) {
            summary.highest_held = rung.rate;
        } else {
            summary.lost_at = rung.rate;
        }
    }
    return out;
}

std::string summary_words(const StormSummary& summary) {
    const auto unit = storm_words(summary.kind).unit;
    if (!summary.highest_held)
        return fmt::format("lost from the first rung ({:g} {})", summary.lost_at.value_or(0), unit);
    const auto lost =
        summary.lost_at ? fmt::format(", lost at {:g}/s", *summary.lost_at) : std::string();
    return fmt::format("held up to {:g} {}{}", *summary.highest_held, unit, lost);
}

std::string storm_requirement(StormKind kind) {
    return holds_resources(kind) ? "CR 7.1 denial-of-service protection; CR 7.2 resource management"
                                 : "CR 7.1 denial-of-service protection";
}

std::string storm_tag(StormKind kind) {
    return holds_resources(kind) ? "CR 7.1, CR 7.2" : "CR 7.1";
}

std::string ladder_text(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                        const std::vector<StormNotRun>& not_run) {
    std::string out;
    const auto all = storm_summaries(judged, rungs);
    auto summary = all.begin();
    for (std::size_t i = 0; i < rungs.size(); ++i) {
        const auto& rung = rungs[i];
        if (i == 0 || rungs[i - 1].kind != rung.kind)
            out += fmt::format("storm ladder ({}):\n", storm_heading(rung.kind));
        out += fmt::format("  {:>8g}/s asked, {}: the monitor {}\n", rung.rate, rung_line(rung),
                           held_at(judged, rung) ? "held" : "was lost");
        if (i + 1 < rungs.size() && rungs[i + 1].kind == rung.kind) continue;
        const auto tag = storm_tag(rung.kind);
        const auto lost =
            summary->lost_at ? fmt::format(", lost at {:g}/s", *summary->lost_at) : std::string();
        out += summary->highest_held
                   ? fmt::format("the monitor held up to {:g} {}{} [{}]\n", *summary->highest_held,
                                 storm_words(rung.kind).unit, lost, tag)
                   : fmt::format("the monitor was lost from the first rung ({:g} {}) [{}]\n",
                                 *summary->lost_at, storm_words(rung.kind).unit, tag);
        ++summary;
    }
    for (const auto& n : not_run) {
        if (!is_request_storm(n.kind))
            out += fmt::format("storm ladder ({}): not run: {}\n", storm_heading(n.kind), n.reason);
    }
    return out + per_function_text(all, not_run);
}

nlohmann::json ladder_json(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs,
                           const std::vector<StormNotRun>& not_run) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& rung : rungs) {
        list.push_back(
            {{"storm", storm_key(rung.kind)},
             {"rate", rung.rate},
             {"duration_ms",
              std::chrono::duration_cast<std::chrono::milliseconds>(rung.end - rung.begin).count()},
             {"sent", rung.sent},
             {"answered", rung.answered},
             {"reconnects", rung.reconnects},
             {"opened", rung.opened},
             {"refused", rung.refused},
             {"held", held_at(judged, rung)}});
        if (rung.address) list.back()["address"] = *rung.address;
    }
    nlohmann::json storms = nlohmann::json::array();
    const auto or_null = [](const std::optional<double>& rate) {
        return rate ? nlohmann::json(*rate) : nlohmann::json(nullptr);
    };
    const auto with_function = [](nlohmann::json row, StormKind kind) {
        if (is_request_storm(kind)) row["function"] = storm_words(kind).function;
        return row;
    };
    for (const auto& s : storm_summaries(judged, rungs)) {
        storms.push_back(with_function({{"storm", storm_key(s.kind)},
                                        {"requirement", storm_tag(s.kind)},
                                        {"highest_rate_held", or_null(s.highest_held)},
                                        {"lost_at", or_null(s.lost_at)}},
                                       s.kind));
    }
    nlohmann::json skipped = nlohmann::json::array();
    for (const auto& n : not_run) {
        skipped.push_back(
            with_function({{"storm", storm_key(n.kind)}, {"reason", n.reason}}, n.kind));
    }
    return {{"rungs", list}, {"storms", storms}, {"not_run", skipped}};
}

}  // namespace mblab::robustness
