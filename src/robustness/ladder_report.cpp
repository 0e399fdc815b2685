#include "robustness/ladder_report.hpp"

#include <fmt/core.h>

#include <optional>

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

struct StormSummary {
    StormKind kind = StormKind::Fc03;
    std::optional<double> highest_held;  // held at every rung up to it
    std::optional<double> lost_at;       // the first rung that lost the monitor
};

// One summary per storm, in the order they ran.
std::vector<StormSummary> summaries(const MonitorJudgement& judged,
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

std::string rung_line(const LadderRung& rung) {
    const auto seconds =
        std::max(1e-3, std::chrono::duration<double>(rung.end - rung.begin).count());
    const auto per_second = [&](std::size_t n) { return static_cast<double>(n) / seconds; };
    switch (rung.kind) {
        case StormKind::Fc03:
            return fmt::format("{:>8.0f}/s sent, {:>8.0f}/s answered, {} reconnect(s)",
                               per_second(rung.sent), per_second(rung.answered), rung.reconnects);
        case StormKind::Opens:
            return fmt::format("{:>8.0f}/s opened, {} refused", per_second(rung.opened),
                               rung.refused);
        case StormKind::SlowReaders:
            return fmt::format("{} held unread with {} requests written, {} refused", rung.opened,
                               rung.sent, rung.refused);
        case StormKind::HalfOpen:
            return fmt::format("{} left half-open, {} refused", rung.opened, rung.refused);
    }
    return {};
}

}  // namespace

std::string storm_requirement(StormKind kind) {
    return kind == StormKind::Fc03 || kind == StormKind::Opens
               ? "CR 7.1 denial-of-service protection"
               : "CR 7.1 denial-of-service protection; CR 7.2 resource management";
}

std::string ladder_text(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs) {
    std::string out;
    const auto all = summaries(judged, rungs);
    auto summary = all.begin();
    for (std::size_t i = 0; i < rungs.size(); ++i) {
        const auto& rung = rungs[i];
        if (i == 0 || rungs[i - 1].kind != rung.kind)
            out += fmt::format("storm ladder ({}):\n", storm_words(rung.kind).heading);
        out += fmt::format("  {:>8g}/s asked, {}: the monitor {}\n", rung.rate, rung_line(rung),
                           held_at(judged, rung) ? "held" : "was lost");
        if (i + 1 < rungs.size() && rungs[i + 1].kind == rung.kind) continue;
        const auto tag = rung.kind == StormKind::Fc03 || rung.kind == StormKind::Opens
                             ? "CR 7.1"
                             : "CR 7.1, CR 7.2";
        const auto lost =
            summary->lost_at ? fmt::format(", lost at {:g}/s", *summary->lost_at) : std::string();
        out += summary->highest_held
                   ? fmt::format("the monitor held up to {:g} {}{} [{}]\n", *summary->highest_held,
                                 storm_words(rung.kind).unit, lost, tag)
                   : fmt::format("the monitor was lost from the first rung ({:g} {}) [{}]\n",
                                 *summary->lost_at, storm_words(rung.kind).unit, tag);
        ++summary;
    }
    return out;
}

nlohmann::json ladder_json(const MonitorJudgement& judged, const std::vector<LadderRung>& rungs) {
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
    }
    nlohmann::json storms = nlohmann::json::array();
    const auto or_null = [](const std::optional<double>& rate) {
        return rate ? nlohmann::json(*rate) : nlohmann::json(nullptr);
    };
    for (const auto& s : summaries(judged, rungs)) {
        storms.push_back({{"storm", storm_key(s.kind)},
                          {"highest_rate_held", or_null(s.highest_held)},
                          {"lost_at", or_null(s.lost_at)}});
    }
    return {{"rungs", list}, {"storms", storms}};
}

}  // namespace mblab::robustness
