#include "conformance/client_judge.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <regex>
#include <set>
#include <string_view>

#include "support/escaped_text.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

// A client may resend a little before its timeout runs out by the clock of the examiner.
constexpr double kEarlyResend = 0.8;
// How long after its last try's timeout a client may take to end and say so.
constexpr auto kEndSlack = 1500ms;

std::string hex_bytes(std::span<const std::uint8_t> bytes) {
    std::string text;
    for (const auto byte : bytes)
        text += fmt::format("{}{:02X}", text.empty() ? "" : " ", byte);
    return text;
}

// The client's output on one line, cut to a readable length, for a reason. A client may print
// what it received as it came (openssl s_client does): bytes that are not printable ASCII are
// shown as \xNN, so that the reason stays text a report can carry.
std::string quoted(std::string_view output) {
    constexpr std::size_t kShown = 160;
    while (!output.empty() && std::isspace(static_cast<unsigned char>(output.back())))
        output.remove_suffix(1);
    std::string line;
    for (const char c : output) {
        if (line.size() >= kShown) {
            line += "...";
            break;
        }
        if (c == '\n' || c == '\r' || c == '\t') {
            line += ' ';
        } else {
            append_escaped(line, static_cast<std::uint8_t>(c));
        }
    }
    return "output: \"" + line + "\"";
}

std::vector<std::uint32_t> values_in(const std::string& output, const std::string& pattern) {
    std::vector<std::uint32_t> values;
    std::regex value;
    try {
        value = std::regex(pattern, std::regex::ECMAScript | std::regex::multiline);
    } catch (const std::regex_error&) {
        return values;  // the command line checked it
    }
    for (auto it = std::sregex_iterator(output.begin(), output.end(), value);
         it != std::sregex_iterator(); ++it) {
        const auto& match = *it;
        const std::string text =
            match.size() > 1 && match[1].matched ? match[1].str() : match.str();
        try {
            const auto number = std::stoul(text, nullptr, text.starts_with("0x") ? 16 : 10);
            values.push_back(static_cast<std::uint32_t>(number));
        } catch (const std::exception&) {
        }
    }
    return values;
}

bool signalled_error(const ClientRun& run, const ClientDeclarations& declared) {
    if (run.stopped) return false;
    if (declared.error_pattern.empty()) return run.exit_status != 0;
    try {
        return std::regex_search(run.output, std::regex(declared.error_pattern));
    } catch (const std::regex_error&) {
        return run.exit_status != 0;
    }
}

struct Facts {
    std::vector<const ClientExaminer::Request*> asked;  // to the declared unit
    std::vector<std::uint32_t> values;
    std::optional<std::uint32_t> decoy;  // the first decoy the output shows
    bool right = false;                  // every seeded value the client read shows
    bool error = false;
};

Facts facts_of(const ClientExaminer& exam, const ClientDeclarations& declared,
               const ClientRun& run) {
    Facts facts;
    for (const auto& request : exam.requests())
        if (request.unit == declared.unit) facts.asked.push_back(&request);
    facts.values = values_in(run.output, declared.value_pattern);
    std::set<std::uint32_t> decoys;
    std::set<std::uint32_t> seeded;
    for (const auto* request : facts.asked) {
        for (std::uint32_t i = 0; i <= request->count; ++i)
            decoys.insert(decoy_value(request->address + i));
        for (std::uint32_t i = 0; i < request->count; ++i)
            seeded.insert(seeded_value(request->address + i));
    }
    for (const auto value : facts.values) {
        if (!facts.decoy && decoys.contains(value)) facts.decoy = value;
        seeded.erase(value);
    }
    facts.right = !facts.asked.empty() && seeded.empty();
    facts.error = signalled_error(run, declared);
    return facts;
}

Outcome pass(std::string remark = {}) {
    return {Verdict::Pass, std::move(remark), {}, {}};
}
Outcome fail(std::string reason, const ClientRun& run) {
    return {Verdict::Fail, reason + "; " + quoted(run.output), {}, {}};
}

// The decoy answer whose value the client showed.
std::string decoy_source(const ClientExaminer& exam, std::uint32_t value) {
    for (const auto& answer : exam.answers()) {
        if (!answer.decoy) continue;
        for (std::size_t i = 0; i + 1 < answer.bytes.size(); ++i) {
            if (static_cast<std::uint32_t>(answer.bytes[i] << 8 | answer.bytes[i + 1]) == value)
                return "from " + hex_bytes(answer.bytes);
        }
    }
    return "";
}

Outcome took_decoy(const ClientExaminer& exam, const Facts& facts, const ClientRun& run) {
    return fail(fmt::format("took the decoy {} {}", *facts.decoy, decoy_source(exam, *facts.decoy)),
                run);
}

unsigned tries_of(const ClientDeclarations& declared) {
    return declared.retries.value_or(0) + 1;
}

Outcome judge_no_reply(const ClientExaminer&, const ClientDeclarations& declared,
                       const ClientRun& run, const Facts& facts) {
    const auto timeout = *declared.timeout;
    const auto tries = tries_of(declared);
    if (facts.asked.size() > tries) {
        return fail(fmt::format("sent {} requests where {} retries make {}: a resend storm",
                                facts.asked.size(), *declared.retries, tries),
                    run);
    }
    if (run.stopped) {
        return fail(fmt::format("still waiting {} ms after its first request, with a declared "
                                "timeout of {} ms and {} retries: it never timed out",
                                run.limit.count(), timeout.count(), *declared.retries),
                    run);
    }
    if (facts.asked.size() < tries) {
        return fail(fmt::format("sent {} requests where {} retries make {}", facts.asked.size(),
                                *declared.retries, tries),
                    run);
    }
    for (std::size_t i = 1; i < facts.asked.size(); ++i) {
        const auto gap = std::chrono::duration_cast<std::chrono::milliseconds>(
            facts.asked[i]->at - facts.asked[i - 1]->at);
        if (gap.count() < static_cast<long>(kEarlyResend * static_cast<double>(timeout.count()))) {
            return fail(fmt::format("resent after {} ms, before its {} ms timeout ran out",
                                    gap.count(), timeout.count()),
                        run);
        }
    }
    if (run.elapsed > timeout * tries + kEndSlack) {
        return fail(
            fmt::format("ended after {} ms; {} tries of {} ms make {} ms", run.elapsed.count(),
                        tries, timeout.count(), (timeout * tries).count()),
            run);
    }
    if (run.attached) {
        return pass(fmt::format("{} request{}, each after its timeout", facts.asked.size(),
                                facts.asked.size() == 1 ? "" : "s"));
    }
    if (!facts.error) return fail("reported success without an answer", run);
    return pass(fmt::format("{} request{}, then an error", facts.asked.size(),
                            facts.asked.size() == 1 ? "" : "s"));
}

// The answer the client took must be its own: the right values, without an error.
Outcome judge_kept_waiting(const ClientExaminer& exam, const ClientRun& run, const Facts& facts,
                           const std::string& what) {
    if (facts.decoy) return took_decoy(exam, facts, run);
    if (run.stopped) return fail("never ended", run);
    if (facts.error || !facts.right) {
        return fail(what.empty()
                        ? "did not take its own answer"
                        : "reported an error instead of discarding " + what + " and taking its own",
                    run);
    }
    return pass();
}

Outcome judge_rejected(const ClientExaminer& exam, const ClientRun& run, const Facts& facts) {
    if (facts.decoy) return took_decoy(exam, facts, run);
    if (run.stopped) return fail("never ended", run);
    if (facts.error) return pass("rejected with an error");
    if (facts.right && facts.asked.size() > 1) return pass("discarded it and took a later answer");
    return fail("ended successfully without the values it was sent", run);
}

// Words that name each code in a client's output, lower case: its name in [APP] 7 or the "slave
// device" wording libraries keep (libmodbus prints "Slave device or server failure" for 04);
// `unless` rules out the name of another code that holds them.
struct ExceptionWords {
    std::uint8_t code;
    std::string_view words;
    std::string_view also = {};
    std::string_view unless = {};
};
constexpr ExceptionWords kExceptionWords[] = {
    {0x01, "illegal function"},
    {0x02, "illegal data address"},
    {0x03, "illegal data value"},
    {0x04, "device failure", "server failure"},
    {0x05, "acknowledge", {}, "negative acknowledge"},
    {0x06, "busy"},
    {0x07, "negative acknowledge"},
    {0x08, "parity"},
    {0x0A, "path unavailable"},
    {0x0B, "failed to respond"},
};

// Whether a client's output names exception `code`: by its number (hex, or "exception N"), or in
// words.
bool names_exception(const std::string& output, std::uint8_t code) {
    if (output.find(fmt::format("{:02X}", code)) != std::string::npos ||
        output.find("exception " + std::to_string(code)) != std::string::npos)
        return true;
    std::string text(output.size(), ' ');
    std::transform(output.begin(), output.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto has = [&](std::string_view words) {
        return !words.empty() && text.find(words) != std::string::npos;
    };
    const auto* row = std::find_if(std::begin(kExceptionWords), std::end(kExceptionWords),
                                   [&](const ExceptionWords& w) { return w.code == code; });
    return row != std::end(kExceptionWords) && (has(row->words) || has(row->also)) &&
           !has(row->unless);
}

Outcome judge_exception(const ClientExaminer& exam, const ClientDeclarations& declared,
                        const ClientRun& run, const Facts& facts) {
    const auto code = exam.scenario().exception;
    if (run.stopped) return fail("never ended", run);
    if (!facts.error && !run.attached) {
        return fail(fmt::format("exception {:02X} reported as success, not as an error", code),
                    run);
    }
    // APP 7: 05, 06 and 0B are the codes that say "ask again later"; the others answer the same.
    const bool may_retry = code == 0x05 || code == 0x06 || code == 0x0B;
    const std::size_t allowed = may_retry ? tries_of(declared) : 1;
    // Another request (a client explaining an 02 by reading around it) is no retry.
    const auto& first = *facts.asked.front();
    const auto repeats = std::count_if(facts.asked.begin(), facts.asked.end(), [&](const auto* r) {
        return r->function == first.function && r->address == first.address &&
               r->count == first.count;
    });
    if (static_cast<std::size_t>(repeats) > allowed) {
        return fail(fmt::format("asked {} times after exception {:02X}", repeats, code), run);
    }
    if (run.attached) return pass(fmt::format("asked {} time{}", repeats, repeats == 1 ? "" : "s"));
    return pass(names_exception(run.output, code) ? "an error naming the code"
                                                  : "an error (its output does not name the code)");
}

Outcome judge_close(const ClientExaminer& exam, const ClientDeclarations& declared,
                    const ClientRun& run, const Facts& facts) {
    if (facts.decoy) return took_decoy(exam, facts, run);
    if (run.stopped) return fail("never ended after the connection closed", run);
    const auto tries = declared.retries ? tries_of(declared) : 3U;
    // Connections that carried no request (a client checking whether the port speaks TLS) are
    // no resend.
    std::set<std::size_t> carried;
    for (const auto* request : facts.asked)
        carried.insert(request->connection);
    if (carried.size() > tries || facts.asked.size() > tries) {
        return fail(fmt::format("{} connections and {} requests for {} tries: a burst",
                                carried.size(), facts.asked.size(), tries),
                    run);
    }
    if (run.attached) {
        return pass(fmt::format("no burst: {} connection{} and {} request{}", carried.size(),
                                carried.size() == 1 ? "" : "s", facts.asked.size(),
                                facts.asked.size() == 1 ? "" : "s"));
    }
    if (facts.right && !facts.error) return pass("reconnected and asked again");
    if (facts.error) return pass("an error, no burst");
    return fail("ended successfully without the values it was sent", run);
}

Outcome judge_pipelined(const ClientExaminer& exam, const ClientRun& run, const Facts& facts) {
    if (facts.decoy) return took_decoy(exam, facts, run);
    if (run.stopped) return fail("never ended", run);
    if (facts.error || !facts.right) return fail("did not show every request's own values", run);
    // Each request's first value shows in the order the requests went out.
    std::size_t last = 0;
    for (const auto* request : facts.asked) {
        const auto value = seeded_value(request->address);
        const auto at = std::find(facts.values.begin(), facts.values.end(), value);
        const auto index = static_cast<std::size_t>(at - facts.values.begin());
        if (index < last) return fail("values out of order: matched by arrival, not by id", run);
        last = index;
    }
    return pass();
}

// SER 2.4.1 gives a turnaround delay of typically 100 to 200 ms; its floor is the least a
// master may leave the slaves to execute a broadcast.
constexpr auto kTurnaround = 100ms;

Outcome judge_broadcast(const ClientDeclarations& declared, const ClientRun& run,
                        const Facts& facts) {
    if (run.stopped) return fail("never ended after a broadcast", run);
    if (facts.error) return fail("reported an error for a broadcast, which no device answers", run);
    const auto after =
        std::chrono::duration_cast<std::chrono::milliseconds>(run.ended - facts.asked.back()->at);
    if (after >= *declared.timeout) {
        return fail(fmt::format("ended {} ms after its broadcast, its timeout being {} ms: it "
                                "waited for an answer",
                                after.count(), declared.timeout->count()),
                    run);
    }
    const auto& requests = facts.asked;
    for (std::size_t i = 1; i < requests.size(); ++i) {
        const auto gap = std::chrono::duration_cast<std::chrono::milliseconds>(requests[i]->at -
                                                                               requests[i - 1]->at);
        if (gap < kTurnaround) {
            return fail(fmt::format("sent its next request {} ms after a broadcast, within the "
                                    "{} ms turnaround delay",
                                    gap.count(), kTurnaround.count()),
                        run);
        }
    }
    return pass(fmt::format("ended {} ms after its broadcast", after.count()));
}

// SEC R-06: a client that goes on past a certificate it cannot verify has been told its values by
// whoever holds the key. The examiner answers such a request with decoys.
Outcome judge_untrusted(const ClientExaminer& exam, const ClientDeclarations& declared,
                        const ClientRun& run) {
    const auto& flaw = exam.scenario().flaw;
    if (!exam.requests().empty()) {
        const auto& request = exam.requests().front();
        const auto facts = facts_of(exam, declared, run);
        return fail(
            fmt::format("took a server certificate {}: sent {} inside the session{}", flaw,
                        hex_bytes(request.adu),
                        facts.decoy ? fmt::format(" and showed the decoy {}", *facts.decoy) : ""),
            run);
    }
    if (run.attached) {
        if (exam.refusals().empty()) return pass("no request inside the session");
        return pass("refused the handshake: " + exam.refusals().front());
    }
    if (run.stopped) return fail("never ended", run);
    if (!signalled_error(run, declared)) {
        return fail("sent no request yet reported success, not the refusal", run);
    }
    if (exam.refusals().empty()) return pass("no request, then an error");
    return pass("refused the handshake: " + exam.refusals().front());
}

}  // namespace

std::chrono::milliseconds client_run_limit(const ClientDeclarations& declared) {
    const auto timeout = declared.timeout.value_or(1000ms);
    return 2 * timeout * tries_of(declared) + 3000ms;
}

Outcome judge_client(const ClientExaminer& exam, const ClientDeclarations& declared,
                     const ClientRun& run) {
    if (auto na = undeclared(exam.scenario(), declared)) return *na;
    if (run.attached && run.stopped && exam.requests().empty() && exam.refusals().empty()) {
        return {Verdict::NotRun,
                fmt::format("the client sent nothing within {} ms of waiting (--attach-wait)",
                            run.elapsed.count()),
                {},
                {}};
    }
    if (exam.scenario().scenario == ClientScenario::Untrusted)
        return judge_untrusted(exam, declared, run);
    const auto facts = facts_of(exam, declared, run);
    if (facts.asked.empty()) {
        return fail(fmt::format("sent no request to unit {} (exit status {})", declared.unit,
                                run.exit_status),
                    run);
    }
    switch (exam.scenario().scenario) {
        case ClientScenario::NoReply:
            return judge_no_reply(exam, declared, run, facts);
        case ClientScenario::LateReply:
            if (facts.decoy) return took_decoy(exam, facts, run);
            if (!exam.stale_met_a_wait()) {
                return {Verdict::NotApplicable,
                        "the client did not ask again on the same connection under a new "
                        "transaction id, so the stale answer met no wait",
                        {},
                        {}};
            }
            return judge_kept_waiting(exam, run, facts, "the stale answer");
        case ClientScenario::WrongTransaction:
            return judge_kept_waiting(exam, run, facts, "the wrong transaction id's answer");
        case ClientScenario::WrongUnit:
            return judge_kept_waiting(exam, run, facts, "the other unit's answer");
        case ClientScenario::SplitAnswer:
        case ClientScenario::TwoAnswers:
            return judge_kept_waiting(exam, run, facts, "");
        case ClientScenario::WrongFunction:
        case ClientScenario::Truncated:
        case ClientScenario::ExtraBytes:
        case ClientScenario::ByteCount:
        case ClientScenario::BadCheck:
            return judge_rejected(exam, run, facts);
        case ClientScenario::Exception:
            return judge_exception(exam, declared, run, facts);
        case ClientScenario::CloseFin:
        case ClientScenario::CloseReset:
            return judge_close(exam, declared, run, facts);
        case ClientScenario::Pipelined:
            return judge_pipelined(exam, run, facts);
        case ClientScenario::Broadcast:
            return judge_broadcast(declared, run, facts);
        case ClientScenario::Untrusted:
            break;
    }
    return pass();
}

}  // namespace mblab::conformance
