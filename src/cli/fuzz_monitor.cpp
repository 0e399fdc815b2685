#include "cli/fuzz_monitor.hpp"

#include <fmt/core.h>

#include <thread>

#include "client/raw_link.hpp"
#include "protocol/request.hpp"
#include "robustness/fuzz_progress.hpp"
#include "robustness/iec62443_report.hpp"
#include "robustness/ladder_report.hpp"
#include "robustness/monitor_html.hpp"
#include "robustness/monitor_junit.hpp"

namespace mblab::cli {

namespace rb = mblab::robustness;

namespace {

std::chrono::milliseconds of_seconds(double seconds) {
    return std::chrono::milliseconds(static_cast<long>(seconds * 1000));
}

}  // namespace

std::string FuzzMonitor::check(const MonitorChoice& choice) {
    if (const auto spec = rb::parse_monitor_spec(choice.spec, {}); !spec) return spec.error();
    if (!choice.ladder.empty() && choice.spec.empty())
        return "--ladder needs --monitor: the ladder reports the rate it held at";
    if (const auto ladders = rb::parse_ladders(choice.ladder); !ladders) return ladders.error();
    return {};
}

protocol::Result<std::unique_ptr<FuzzMonitor>, std::string> FuzzMonitor::make(
    const MonitorChoice& choice, const client::Target& target, const rb::Recon& recon,
    const rb::WritePolicy& policy, std::chrono::milliseconds timeout) {
    if (choice.spec.empty()) return std::unique_ptr<FuzzMonitor>();
    if (client::framing_of(target) != client::Framing::Mbap)
        return std::string(
            "--monitor: a serial line has one link, which the cases hold: the monitor needs a "
            "connection of its own (tcp:// or mbaps://)");
    rb::MonitorSpec defaults;
    defaults.unit = recon.unit;
    defaults.address = recon.check_address;
    auto spec = rb::parse_monitor_spec(choice.spec, defaults);
    if (!spec) return spec.error();
    const auto write =
        protocol::encoded_pdu(protocol::WriteSingleRegisterRequest{spec->address, 1});
    // Naming the register gives leave to write it; the liveness check's register, the default, is
    // written only where the write policy allows it.
    const bool named = choice.spec.find("register=") != std::string::npos;
    if (!spec->read_only && !named && !rb::may_send(write, policy)) {
        return fmt::format(
            "--monitor writes holding register {}: name the register it may write "
            "(--monitor register=N, one the cases do not write), or watch it with --monitor "
            "read-only",
            spec->address);
    }
    auto parsed = rb::parse_ladders(choice.ladder);
    if (!parsed) return parsed.error();
    std::vector<rb::Ladder> ladders = std::move(parsed).value();
    for (const auto& ladder : ladders) {
        if (ladder.kind == rb::StormKind::HalfOpen && !client::RawLink::can_vanish())
            return std::string(
                "--ladder half-open: leaving a connection half-open needs CAP_NET_ADMIN (TCP "
                "repair mode), which this process lacks");
    }
    rb::StormTarget storms;
    storms.dial = [target, timeout] { return client::open_link(target, timeout, nullptr); };
    storms.unit = spec->unit;
    storms.address = spec->address;
    storms.large_address = recon.check_address;
    storms.large_quantity = recon.max_read;
    storms.timeout = timeout;
    return std::make_unique<FuzzMonitor>(*spec, std::move(storms), choice,
                                         rb::plan_ladders(ladders, recon, policy, spec->address));
}

FuzzMonitor::FuzzMonitor(rb::MonitorSpec spec, rb::StormTarget storms, const MonitorChoice& choice,
                         std::vector<rb::PlannedLadder> ladders)
    : spec_(spec),
      storms_(std::move(storms)),
      run_(spec, storms_.dial),
      ladders_(std::move(ladders)),
      ladder_step_(of_seconds(choice.ladder_step_s)),
      baseline_(of_seconds(choice.baseline_s)),
      degraded_limit_(of_seconds(choice.degraded_limit_s)) {}

void FuzzMonitor::ladder(bool live) {
    const auto progress = [&](std::size_t done, std::size_t total, const std::string& phase) {
        if (!live) return;
        fmt::print(stderr, "\r\033[K{}",
                   rb::ladder_progress_text(done, total, ladder_step_, phase));
        std::fflush(stderr);
    };
    ladder_ = rb::run_ladders(storms_, ladders_, ladder_step_, progress);
    if (live) fmt::print(stderr, "\r\033[K");
    for (const auto& rung : ladder_.rungs) {
        phases_.push_back({rb::storm_phase_name(rung.kind, rung.rate),
                           rb::storm_requirement(rung.kind), rung.begin, rung.end});
    }
}

void FuzzMonitor::baseline() {
    const auto begin = rb::Clock::now();
    run_.start();
    std::this_thread::sleep_for(baseline_);
    phases_.push_back({"baseline", "reference for CR 7.1 and CR 7.2: the monitor alone", begin,
                       rb::Clock::now()});
}

void FuzzMonitor::malformed_begin() {
    phases_.push_back({std::string(rb::kCasesPhase),
                       "CR 3.5 input validation; CR 7.1 denial-of-service protection; CR 7.2 "
                       "resource management",
                       rb::Clock::now(), rb::Clock::time_point::max()});
}

void FuzzMonitor::recover() {
    const auto begin = rb::Clock::now();
    phases_.back().end = begin;
    run_.wait_held(begin, degraded_limit_ + spec_.period);
    // A few periods more: back means staying back.
    std::this_thread::sleep_for(spec_.period * 5);
    run_.stop();
    phases_.push_back({"recovery",
                       "CR 7.1 denial-of-service protection; CR 3.6 deterministic "
                       "output: back without a restart",
                       begin, rb::Clock::now()});
    cycles_ = run_.cycles();
}

rb::MonitorJudgement FuzzMonitor::judge(const rb::FuzzResult& result) const {
    auto judged = rb::judge_monitor(cycles_, spec_, phases_, degraded_limit_);
    judged.missed_during = rb::missed_during(cycles_, result.timeline, spec_.budget);
    if (!result.findings.empty()) {
        // A device that stopped serving the check failed, whatever the monitor saw around it.
        judged.verdict = rb::MonitorVerdict::Fail;
        judged.why = fmt::format("the device stopped serving ({} finding(s)); {}",
                                 result.findings.size(), judged.why);
    }
    return judged;
}

std::string FuzzMonitor::text(const rb::MonitorJudgement& judged) const {
    return rb::monitor_text(judged, spec_) +
           rb::ladder_text(judged, ladder_.rungs, ladder_.not_run);
}

nlohmann::json FuzzMonitor::json(const rb::MonitorJudgement& judged) const {
    auto out = rb::monitor_json(judged, spec_, cycles_);
    if (!ladder_.rungs.empty() || !ladder_.not_run.empty())
        out["ladder"] = rb::ladder_json(judged, ladder_.rungs, ladder_.not_run);
    return out;
}

std::string FuzzMonitor::html(const rb::FuzzResult& result,
                              const rb::MonitorJudgement& judged) const {
    return rb::monitor_html(result, judged, spec_, cycles_, ladder_.rungs, ladder_.not_run);
}

rb::JunitSuite FuzzMonitor::junit(const rb::MonitorJudgement& judged) const {
    return rb::monitor_junit_suite(judged, ladder_.rungs, ladder_.not_run);
}

}  // namespace mblab::cli
