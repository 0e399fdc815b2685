#include "cli/fuzz_monitor.hpp"

#include <fmt/core.h>

#include <thread>

#include "robustness/iec62443_report.hpp"

namespace mblab::cli {

namespace rb = mblab::robustness;

namespace {

std::chrono::milliseconds of_seconds(double seconds) {
    return std::chrono::milliseconds(static_cast<long>(seconds * 1000));
}

}  // namespace

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
    const std::vector<std::uint8_t> write = {0x06, static_cast<std::uint8_t>(spec->address >> 8),
                                             static_cast<std::uint8_t>(spec->address), 0, 1};
    // Naming the register is leave to write it; the liveness check's register, the default, is
    // written only where the write policy allows it.
    const bool named = choice.spec.find("register=") != std::string::npos;
    if (!spec->read_only && !named && !rb::may_send(write, policy)) {
        return fmt::format(
            "--monitor writes holding register {}: name the register it may write "
            "(--monitor register=N, one the cases do not write), or watch it with --monitor "
            "read-only",
            spec->address);
    }
    client::Dial dial = [target, timeout] { return client::open_link(target, timeout, nullptr); };
    return std::make_unique<FuzzMonitor>(*spec, std::move(dial), of_seconds(choice.baseline_s),
                                         of_seconds(choice.degraded_limit_s));
}

FuzzMonitor::FuzzMonitor(rb::MonitorSpec spec, client::Dial dial,
                         std::chrono::milliseconds baseline,
                         std::chrono::milliseconds degraded_limit)
    : spec_(spec),
      run_(spec, std::move(dial)),
      baseline_(baseline),
      degraded_limit_(degraded_limit) {}

void FuzzMonitor::baseline() {
    const auto begin = rb::Clock::now();
    run_.start();
    std::this_thread::sleep_for(baseline_);
    phases_.push_back({"baseline", "reference for CR 7.1 and CR 7.2: the monitor alone", begin,
                       rb::Clock::now()});
}

void FuzzMonitor::malformed_begin() {
    phases_.push_back({"malformed input",
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
    if (!result.findings.empty()) {
        // A device that stopped serving the check failed, whatever the monitor saw around it.
        judged.verdict = rb::MonitorVerdict::Fail;
        judged.why = fmt::format("the device stopped serving ({} finding(s)); {}",
                                 result.findings.size(), judged.why);
    }
    return judged;
}

std::string FuzzMonitor::text(const rb::MonitorJudgement& judged) const {
    return rb::monitor_text(judged, spec_);
}

nlohmann::json FuzzMonitor::json(const rb::MonitorJudgement& judged) const {
    return rb::monitor_json(judged, spec_, cycles_);
}

}  // namespace mblab::cli
