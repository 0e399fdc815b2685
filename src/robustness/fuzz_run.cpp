#include "robustness/fuzz_run.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <thread>

#include "robustness/line_cases.hpp"
#include "robustness/minimise.hpp"

namespace mblab::robustness {

namespace {

using Clock = std::chrono::steady_clock;

// Steps larger than this are streamed, their answers read while they are written: a device that
// answers as it reads must not find its answers piling up unread.
constexpr std::size_t kStreamAbove = 64 * 1024;
constexpr std::size_t kStreamChunk = 16 * 1024;
// How long a slow reader's requests are written for: once the device stops taking them its
// buffers are full, which is all the case needs, and a device that reads slowly is not waited on.
constexpr std::chrono::milliseconds kSlowReaderWindow{250};

// Calls `visit` with the PDU of each whole MBAP frame at the start of `bytes`; returns how many.
template <class Visit>
std::size_t each_frame(std::span<const std::uint8_t> bytes, Visit&& visit) {
    std::size_t count = 0;
    for (std::size_t at = 0; at + 7 <= bytes.size(); ++count) {
        const std::size_t length = bytes[at + 4] << 8 | bytes[at + 5];
        if (length < 2 || at + 6 + length > bytes.size()) break;
        visit(bytes.subspan(at + 7, length - 1));
        at += 6 + length;
    }
    return count;
}

// The highest FC 06 value to `address` among MBAP frames in `bytes`.
std::uint16_t highest_write(std::span<const std::uint8_t> bytes, std::uint16_t address) {
    std::uint16_t highest = 0;
    each_frame(bytes, [&](std::span<const std::uint8_t> pdu) {
        if (pdu.size() == 5 && pdu[0] == 0x06 && (pdu[1] << 8 | pdu[2]) == address)
            highest = std::max(highest, static_cast<std::uint16_t>(pdu[3] << 8 | pdu[4]));
    });
    return highest;
}

}  // namespace

FuzzRunner::FuzzRunner(FuzzOptions options, Recon recon, client::LinkObserver* observer)
    : options_(std::move(options)),
      recon_(std::move(recon)),
      observer_(observer),
      line_(client::framing_of(options_.target) != client::Framing::Mbap),
      oracle_(options_.target, recon_.unit, recon_.check_address, options_.timeout, observer),
      line_oracle_(recon_.unit, recon_.check_address, options_.timeout, options_.quiet) {}

Liveness FuzzRunner::check() {
    if (!line_) return oracle_.check();
    if (links_.empty()) links_.resize(1);
    auto& link = links_.front();
    // RTU over TCP: the link is a connection, and closing it on bad input is the device's right
    // as over Modbus/TCP; a fresh one must then be served. A serial port that closes has failed.
    const bool connection = options_.target.serial &&
                            options_.target.serial->kind == transport::SerialUrl::Kind::RtuOverTcp;
    Liveness earlier;
    for (int attempt = 0; attempt < (connection ? 2 : 1); ++attempt) {
        if (!link || !link->is_open()) {
            auto opened = client::open_link(options_.target, options_.timeout, observer_);
            if (!opened) {
                Liveness dead;
                dead.alive = false;
                dead.reason = fmt::format("cannot be reached ({})", opened.error().message);
                dead.waited = earlier.waited;
                return dead;
            }
            link = std::move(opened.value());
        }
        auto liveness = line_oracle_.check(*link);
        liveness.waited += earlier.waited;
        if (liveness.alive || link->is_open()) return liveness;
        earlier = liveness;
    }
    return earlier;
}

Liveness FuzzRunner::wait_alive() {
    if (!line_) return oracle_.wait_alive(options_.restart_patience);
    const auto start = Clock::now();
    while (true) {
        auto liveness = check();
        if (liveness.alive || Clock::now() - start >= options_.restart_patience) return liveness;
        close_all();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

void FuzzRunner::drain_line() {
    auto& link = links_.front();
    // Bounded: a device that talks without end is the oracle's to judge.
    for (int i = 0; i < 64 && link && link->is_open(); ++i) {
        const auto got =
            link->receive_any(i == 0 ? std::max(options_.settle, options_.quiet) : options_.quiet);
        if (got.status == client::ReceiveStatus::Closed) link.reset();
        if (got.status != client::ReceiveStatus::Frame && got.bytes.empty()) return;
    }
}

void FuzzRunner::pace() {
    ++sends_;
    if (options_.rate <= 0) return;
    const auto now = Clock::now();
    if (next_send_ > now) std::this_thread::sleep_until(next_send_);
    next_send_ =
        std::max(now, next_send_) + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(1.0 / options_.rate));
}

void FuzzRunner::send_steps(const std::vector<Step>& steps, bool hold,
                            const std::optional<WriteLedger>& ledger) {
    // One refused connection is enough to judge: a device that has stopped accepting would
    // otherwise cost a connect timeout for each of a thousand connections.
    bool refused = false;
    for (const auto& step : steps) {
        const std::size_t connection = line_ ? 0 : step.connection;
        if (links_.size() <= connection) {
            links_.resize(connection + 1);
            unread_.resize(connection + 1, false);
        }
        auto& link = links_[connection];
        if (!link || !link->is_open()) {
            if (refused) continue;
            auto opened = client::open_link(options_.target, options_.timeout, observer_);
            // A refused connection is judged by the oracle, which tries harder.
            if (!opened) {
                refused = true;
                continue;
            }
            link = std::move(opened.value());
        }
        pace();
        client::LinkError error;
        if (ledger || (!line_ && !step.unread && step.bytes.size() > kStreamAbove)) {
            acknowledged_ = std::max(acknowledged_, stream(*link, step, ledger));
        } else if (link->send_for(step.bytes, step.unread ? kSlowReaderWindow : options_.timeout,
                                  error) < step.bytes.size() &&
                   !step.unread) {
            // A device that takes a small request no faster than this is the oracle's to judge.
            link.reset();
            continue;
        }
        if (step.unread) unread_[connection] = true;
        if (step.vanish && link && link->vanish()) {
            link.reset();
            continue;
        }
        if (step.pause.count() > 0) {
            std::this_thread::sleep_for(step.pause);
        } else if (line_) {
            // On a line each step is a frame of its own: its answer is awaited and the line left
            // quiet before the next, in a replay as in the run.
            drain_line();
        }
    }
    // Answers are read, not judged: what a device answers to garbage is conformance's business.
    if (line_) return;
    bool first = true;
    for (std::size_t i = 0; i < links_.size(); ++i) {
        auto& link = links_[i];
        if (!link || !link->is_open() || unread_[i]) continue;
        link->receive_any(first ? options_.settle : std::chrono::milliseconds(1));
        first = false;
    }
    if (!hold) close_all();
}

std::uint16_t FuzzRunner::stream(client::Link& link, const Step& step,
                                 const std::optional<WriteLedger>& ledger) {
    std::uint16_t acknowledged = 0;
    std::size_t answers = 0;
    auto take_answers = [&](std::chrono::milliseconds wait) {
        std::size_t taken = 0;
        while (link.is_open()) {
            const auto answer = link.next_frame(taken == 0 ? wait : std::chrono::milliseconds(0));
            if (answer.status != client::ReceiveStatus::Frame) break;
            ++taken;
            const auto& pdu = answer.pdu;
            if (ledger && pdu.size() == 5 && pdu[0] == 0x06 &&
                (pdu[1] << 8 | pdu[2]) == ledger->address)
                acknowledged =
                    std::max(acknowledged, static_cast<std::uint16_t>(pdu[3] << 8 | pdu[4]));
        }
        answers += taken;
        return taken;
    };
    const std::span<const std::uint8_t> bytes(step.bytes);
    std::size_t sent = 0;
    // A device that reads slowly gets less of the flood, not a longer one.
    const auto give_up = Clock::now() + 2 * options_.timeout;
    auto last_progress = Clock::now();
    while (sent < bytes.size() && link.is_open() && Clock::now() < give_up &&
           Clock::now() - last_progress < options_.timeout) {
        client::LinkError error;
        const std::size_t n =
            link.send_for(bytes.subspan(sent, std::min(kStreamChunk, bytes.size() - sent)),
                          std::chrono::milliseconds(20), error);
        sent += n;
        if (take_answers(std::chrono::milliseconds(0)) > 0 || n > 0) last_progress = Clock::now();
    }
    // The answers still on their way, until each request has one, the device falls quiet, or as
    // long again as the writing was allowed: a slow device's last acknowledgements may go
    // unread, which only weakens the ledger's check, never makes it wrong.
    const std::size_t requests = each_frame(bytes.first(sent), [](auto) {});
    const auto answers_by = Clock::now() + 2 * options_.timeout;
    while (link.is_open() && answers < requests && Clock::now() < answers_by &&
           take_answers(options_.timeout) > 0) {
    }
    return acknowledged;
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

void FuzzRunner::close_all() {
    for (auto& link : links_) {
        if (link) link->close();
    }
    links_.clear();
    unread_.clear();
}

Liveness FuzzRunner::replay(const std::vector<Step>& steps) {
    send_steps(steps, true);
    auto liveness = check();
    close_all();
    return liveness;
}

FuzzResult FuzzRunner::run(CaseGenerator& generator, const FuzzProgress& progress,
                           const std::function<bool()>& stop) {
    FuzzResult result;
    result.target = options_.target.name;
    result.seed = options_.seed;
    result.recon = recon_;
    for (std::size_t i = 0; i < generator.withheld().size(); ++i)
        result.classes[i].withheld = generator.withheld()[i];
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        if (auto why =
                not_applicable(static_cast<BadInput>(i), client::framing_of(options_.target)))
            result.classes[i].not_applicable = *why;
    }
    if (!line_ && !generator.limits().half_open) {
        result.classes[static_cast<std::size_t>(BadInput::HalfOpen)].not_applicable =
            "needs CAP_NET_ADMIN (root) to let a connection go without a FIN (TCP_REPAIR)";
    }
    const auto start = Clock::now();
    if (!line_) oracle_.open_bystander();
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
        } else if (options_.duration && Clock::now() - start >= *options_.duration) {
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
            std::size_t connections = 0;
            for (const auto& step : c.steps) {
                connections = std::max(connections, step.connection + 1);
                since_check.push_back(step);
                since_check.back().connection += connection_base;
                origins.push_back({c.kind, c.name, result.cases});
            }
            // A line is one link: its reproducers name no other connection.
            if (!line_) connection_base += connections;
            acknowledged_ = 0;
            send_steps(c.steps, c.hold_open, c.ledger);
            last = {c.kind, c.name, result.cases};
            if (c.ledger) {
                ledger = c.ledger;
                highest_sent = 0;
                for (const auto& step : c.steps)
                    highest_sent =
                        std::max(highest_sent, highest_write(step.bytes, ledger->address));
            }
            if (++unchecked < options_.check_every && !c.hold_open && !c.ledger) continue;
        }
        unchecked = 0;
        ++result.checks;
        auto liveness = check();
        if (!line_) close_all();
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
        Finding finding;
        finding.kind = last.kind;
        finding.case_name = last.case_name;
        finding.case_number = last.case_number;
        finding.reason = liveness.reason;
        finding.waited = liveness.waited;
        finding.since_check = std::move(since_check);
        finding.origins = std::move(origins);
        if (lost_write) {
            // Delta debugging asks whether the device dies; this device lives and forgets.
            finding.reproducer = finding.since_check;
            finding.minimise_note =
                "not minimised: a lost write is judged over the whole flood, and a replay checks "
                "only that the device still serves";
        } else {
            minimise_finding(finding);
        }
        result.finding = std::move(finding);
        result.stopped_by = "finding";
        break;
    }
    close_all();
    result.one_connection_at_a_time = oracle_.one_at_a_time();
    if (!line_) oracle_.close();
    result.sends = sends_;
    result.elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
    return result;
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
        close_all();
        if (!line_) oracle_.close();
        if (!options_.restart() || !wait_alive().alive) {
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
    // Leave the device running, as it was found.
    if (options_.restart) options_.restart();
}

}  // namespace mblab::robustness
