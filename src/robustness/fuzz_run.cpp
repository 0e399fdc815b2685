#include "robustness/fuzz_run.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "robustness/flood.hpp"
#include "robustness/line_cases.hpp"
#include "robustness/minimise.hpp"

namespace mblab::robustness {

namespace {

// How long a slow reader's requests are written for: once the device stops taking them its
// buffers are full, which is all the case needs, and a device that reads slowly is not waited on.
constexpr std::chrono::milliseconds kSlowReaderWindow{250};

Dial dial_for(const FuzzOptions& options, client::LinkObserver* observer) {
    if (options.dial) return options.dial;
    return [target = options.target, timeout = options.timeout, observer] {
        return client::open_link(target, timeout, observer);
    };
}

}  // namespace

FuzzRunner::FuzzRunner(FuzzOptions options, Recon recon, client::LinkObserver* observer)
    : options_(std::move(options)),
      recon_(std::move(recon)),
      framing_(client::framing_of(options_.target)),
      links_(make_case_links(framing_, dial_for(options_, observer),
                             {options_.settle, options_.quiet}, options_.clock)),
      oracle_(*links_, recon_.unit, recon_.check_address, options_.timeout, options_.clock) {}

void FuzzRunner::pace() {
    ++sends_;
    if (options_.rate <= 0) return;
    const auto now = options_.clock.now();
    options_.clock.sleep_until(next_send_);
    next_send_ =
        std::max(now, next_send_) + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(1.0 / options_.rate));
}

void FuzzRunner::send_steps(const std::vector<Step>& steps, bool hold,
                            const std::optional<WriteLedger>& ledger) {
    // One refused connection is enough to judge: a device that has stopped accepting would
    // otherwise cost a connect timeout for each of a thousand connections. A refused connection
    // is judged by the oracle, which tries harder.
    bool refused = false;
    for (const auto& step : steps) {
        auto* link = links_->carry(step.connection, !refused);
        if (link == nullptr) {
            refused = true;
            continue;
        }
        pace();
        client::LinkError error;
        if (ledger || (!step.unread && step.bytes.size() > kStreamAbove)) {
            acknowledged_ = std::max(acknowledged_,
                                     stream(*link, step, ledger, options_.timeout, options_.clock));
        } else if (link->send_for(step.bytes, step.unread ? kSlowReaderWindow : options_.timeout,
                                  error) < step.bytes.size() &&
                   !step.unread) {
            // A device that takes a small request no faster than this is the oracle's to judge.
            links_->drop(step.connection);
            continue;
        }
        if (step.unread) links_->leave_unread(step.connection);
        if (step.vanish && link->vanish()) {
            links_->drop(step.connection);
            continue;
        }
        // A step's pause is silence kept on purpose (a frame cut by a gap); otherwise the links
        // see to the step's answers as the framing needs, in a replay as in the run.
        if (step.pause.count() > 0) {
            options_.clock.sleep(step.pause);
        } else {
            links_->after_frame(step.connection);
        }
    }
    links_->end_case(hold);
}

std::string FuzzRunner::check_ledger(const WriteLedger& ledger, std::uint16_t acknowledged,
                                     std::uint16_t highest_sent, FuzzResult& result) {
    if (acknowledged == 0) {
        ++result.ledger.unacknowledged;
        return {};
    }
    const auto value = oracle_.read_register(ledger.address);
    // A register that cannot be read back says nothing of the writes.
    if (!value) return {};
    ++result.ledger.floods;
    result.ledger.acknowledged += acknowledged;
    if (*value >= acknowledged && *value <= highest_sent) return {};
    return fmt::format(
        "lost an acknowledged write: register {} reads {} after FC 06 of {} was acknowledged "
        "(the flood wrote 1..{} in order)",
        ledger.address, *value, acknowledged, highest_sent);
}

Liveness FuzzRunner::replay(const std::vector<Step>& steps) {
    send_steps(steps, true);
    auto liveness = oracle_.check();
    links_->close_all();
    return liveness;
}

FuzzResult FuzzRunner::run(CaseGenerator& generator, const FuzzProgress& progress,
                           const std::function<bool()>& stop) {
    const auto& clock = options_.clock;
    FuzzResult result;
    result.target = options_.target.name;
    result.seed = options_.seed;
    result.recon = recon_;
    for (std::size_t i = 0; i < generator.withheld().size(); ++i)
        result.classes[i].withheld = generator.withheld()[i];
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        if (auto why = not_applicable(static_cast<BadInput>(i), framing_)) {
            result.classes[i].not_applicable = *why;
        } else if (!generator.chosen(static_cast<BadInput>(i))) {
            result.classes[i].not_applicable = "not chosen (--class, --skip-class)";
        }
    }
    auto& half_open = result.classes[static_cast<std::size_t>(BadInput::HalfOpen)];
    if (half_open.not_applicable.empty() && !generator.limits().half_open) {
        half_open.not_applicable =
            "needs CAP_NET_ADMIN (root) to let a connection go without a FIN (TCP_REPAIR)";
    }
    const auto start = clock.now();
    oracle_.open_bystander();
    std::vector<Step> since_check;
    std::vector<StepOrigin> origins;
    std::size_t connection_base = 0;
    std::size_t unchecked = 0;
    StepOrigin last;
    std::optional<WriteLedger> ledger;  // of the case just run, read back after the check
    std::uint16_t highest_sent = 0;
    while (true) {
        std::string out_of_budget;
        if (options_.cases && result.cases >= *options_.cases) {
            out_of_budget = "case budget";
        } else if (generator.exhausted()) {
            out_of_budget = "every chosen case";
        } else if (options_.duration && clock.now() - start >= *options_.duration) {
            out_of_budget = "time budget";
        } else if (stop && stop()) {
            out_of_budget = "interrupted";
        }
        if (!out_of_budget.empty()) {
            result.stopped_by = out_of_budget;
            // Cases not followed by a check yet get one, so "no finding" covers them all.
            if (unchecked == 0) break;
        } else {
            FuzzCase c = generator.next();
            ++result.cases;
            ++result.classes[static_cast<std::size_t>(c.kind)].run;
            if (progress) progress(result, c);
            last = {c.kind, c.name, result.cases};
            if (options_.timeline) {
                const auto now = clock.now();
                if (!result.timeline.empty()) result.timeline.back().end = now;
                result.timeline.push_back({result.cases, c.kind, c.name, now, now});
            }
            std::size_t connections = 0;
            for (const auto& step : c.steps) {
                connections = std::max(connections, step.connection + 1);
                since_check.push_back(step);
                since_check.back().connection += connection_base;
                origins.push_back(last);
            }
            connection_base += links_->numbers_taken(connections);
            acknowledged_ = 0;
            send_steps(c.steps, c.hold_open, c.ledger);
            if (c.ledger) {
                ledger = c.ledger;
                highest_sent = highest_write(c.steps, ledger->address);
            }
            if (++unchecked < options_.check_every && !c.hold_open && !c.ledger) continue;
        }
        unchecked = 0;
        ++result.checks;
        auto liveness = oracle_.check();
        links_->end_check();
        result.longest_wait = std::max(result.longest_wait, liveness.waited);
        bool lost_write = false;
        if (liveness.alive && ledger) {
            liveness.reason = check_ledger(*ledger, acknowledged_, highest_sent, result);
            lost_write = !liveness.reason.empty();
            liveness.alive = !lost_write;
        }
        ledger.reset();
        if (liveness.alive) {
            since_check.clear();
            origins.clear();
            connection_base = 0;
            if (!out_of_budget.empty()) break;
            continue;
        }
        Finding finding{.kind = last.kind,
                        .case_name = last.case_name,
                        .case_number = last.case_number,
                        .reason = liveness.reason,
                        .waited = liveness.waited,
                        .since_check = std::move(since_check),
                        .origins = std::move(origins),
                        .reproducer = {},
                        .minimise_note = {},
                        .minimised = false};
        if (lost_write) {
            // Delta debugging asks whether the device dies; this device lives and forgets.
            finding.reproducer = finding.since_check;
            finding.minimise_note =
                "not minimised: a lost write is judged over the whole flood, and a replay checks "
                "only that the device still serves";
        } else {
            minimise_finding(finding);
        }
        result.findings.push_back(std::move(finding));
        if (!options_.keep_going) {
            result.stopped_by = "finding";
            break;
        }
        if (!recover()) {
            result.stopped_by = "finding; the device did not come back";
            break;
        }
        since_check.clear();
        origins.clear();
        connection_base = 0;
        if (!out_of_budget.empty()) break;
    }
    links_->close_all();
    if (!result.timeline.empty()) result.timeline.back().end = clock.now();
    result.one_connection_at_a_time = oracle_.one_at_a_time();
    result.sends = sends_;
    result.elapsed = clock.since(start);
    return result;
}

bool FuzzRunner::recover() {
    links_->close_all();
    if (options_.restart && !options_.restart()) return false;
    if (!oracle_.wait_alive(options_.restart_patience).alive) return false;
    oracle_.open_bystander();
    return true;
}

void FuzzRunner::minimise_finding(Finding& finding) {
    finding.reproducer = finding.since_check;
    if (!options_.restart) {
        finding.minimise_note = "could not minimise (no --restart)";
        return;
    }
    std::size_t replays = 0;
    bool restart_failed = false;
    auto kills = [&](const std::vector<Step>& steps) {
        if (restart_failed) return false;
        links_->close_all();
        if (!options_.restart() || !oracle_.wait_alive(options_.restart_patience).alive) {
            restart_failed = true;
            return false;
        }
        ++replays;
        return !replay(steps).alive;
    };
    if (!kills(finding.since_check)) {
        finding.minimise_note =
            restart_failed
                ? "could not minimise: the device did not answer after --restart"
                : "could not minimise: replaying every frame since the last good check on a "
                  "restarted device did not kill it";
        return;
    }
    const auto kept = minimise(finding.since_check.size(), [&](const std::vector<std::size_t>& at) {
        std::vector<Step> subset;
        for (auto i : at)
            subset.push_back(finding.since_check[i]);
        return kills(subset);
    });
    std::vector<Step> shortest;
    for (auto i : kept)
        shortest.push_back(finding.since_check[i]);
    // When the frames that kill come from one case, that case is the finding's.
    const auto& first = finding.origins[kept.empty() ? 0 : kept.front()];
    if (!kept.empty() && std::all_of(kept.begin(), kept.end(), [&](std::size_t i) {
            return finding.origins[i].case_number == first.case_number;
        })) {
        finding.kind = first.kind;
        finding.case_name = first.case_name;
        finding.case_number = first.case_number;
    }
    // Connections renumbered from 0 in order of first use.
    std::vector<std::size_t> seen;
    for (auto& step : shortest) {
        auto found = std::find(seen.begin(), seen.end(), step.connection);
        if (found == seen.end()) {
            seen.push_back(step.connection);
            found = seen.end() - 1;
        }
        step.connection = static_cast<std::size_t>(found - seen.begin());
    }
    finding.reproducer = std::move(shortest);
    finding.minimised = true;
    finding.minimise_note =
        fmt::format("minimised from {} to {} frame(s) in {} replays", finding.since_check.size(),
                    finding.reproducer.size(), replays);
    // Leave the device running, as it was found; with keep_going the run restarts it once it
    // goes on (a second restart command could race the first's device for its port).
    if (options_.restart && !options_.keep_going) options_.restart();
}

}  // namespace mblab::robustness
