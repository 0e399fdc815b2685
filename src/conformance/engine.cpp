#include "conformance/engine.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>

#include "conformance/answer_rules.hpp"
#include "conformance/judge.hpp"
#include "conformance/procedures.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

namespace {

using Clock = std::chrono::steady_clock;

struct ResolvedStep {
    const Step* step = nullptr;
    std::vector<std::uint8_t> request;
    std::vector<ResolvedPattern> expect;
};

Outcome verdict(Verdict v, std::string reason) {
    return Outcome{v, std::move(reason), {}};
}

std::optional<Outcome> check_requirements(const Case& c, const Dut& dut) {
    for (const auto& requirement : c.requirements) {
        if (auto why = unmet(requirement, dut)) return verdict(Verdict::NotApplicable, *why);
    }
    return std::nullopt;
}

constexpr std::size_t kPduAt = 7;  // the PDU's place in an MBAP frame

bool is_exception(const Exchange& exchange, protocol::ExceptionCode code) {
    return exchange.status == client::ReceiveStatus::Frame &&
           is_exception_answer(exchange.sent, exchange.received, code);
}

std::span<const std::uint8_t> pdu_of(std::span<const std::uint8_t> adu) {
    return adu.size() > kPduAt ? adu.subspan(kPduAt) : std::span<const std::uint8_t>{};
}

// Checks every field the spec fixes in an answer the pattern accepted; the step's failure when
// one is wrong.
std::optional<std::string> spec_failure(const Exchange& exchange) {
    if (exchange.status != client::ReceiveStatus::Frame) return std::nullopt;
    return answer_rule_broken(pdu_of(exchange.sent), pdu_of(exchange.received));
}

constexpr std::uint8_t kEncapsulated = 0x2B;
constexpr std::uint8_t kMeiReadDeviceId = 0x0E;
constexpr std::uint8_t kMoreFollows = 0xFF;
constexpr std::size_t kObjectIdAt = 10;  // in a 2B / 0E request ADU

// The objects of a basic stream from object 00 that [APP] 6.21 makes mandatory.
std::optional<Outcome> missing_basic_objects(const Exchange& first, const std::vector<bool>& seen) {
    std::string missing;
    for (std::uint8_t id = 0; id <= 2; ++id) {
        if (!seen[id]) missing += fmt::format("{}{:02X}", missing.empty() ? "" : ", ", id);
    }
    if (missing.empty()) return std::nullopt;
    return Outcome{Verdict::Fail,
                   fmt::format("basic device identification must hold objects 00 (vendor name), "
                               "01 (product code) and 02 (revision); the stream lacks {}",
                               missing),
                   {first}};
}

// A stream read of device identification (2B / 0E, codes 01..03) whose answer says more
// follows: the same request is asked again from the next object id until none follows. Each
// answer is judged like the first; a stream that asks for an object twice never ends. A basic
// stream from object 00 must have delivered the mandatory objects when it ends.
std::optional<Outcome> follow_device_id_stream(Session& session, const Exchange& first,
                                               std::chrono::milliseconds timeout) {
    const auto& request = first.sent;
    if (request.size() != 11 || request[kPduAt] != kEncapsulated ||
        request[kPduAt + 1] != kMeiReadDeviceId || request[9] < 1 || request[9] > 3) {
        return std::nullopt;
    }
    const bool basic_from_start = request[9] == 1 && request[kObjectIdAt] == 0;
    std::vector<std::uint8_t> answer = first.received;
    std::vector<bool> asked(256, false);
    std::vector<bool> seen(256, false);
    asked[request[kObjectIdAt]] = true;
    for (std::size_t round = 2;; ++round) {
        auto decoded = protocol::decode_response(pdu_of(answer));
        if (!decoded) return std::nullopt;  // judged by the spec check already
        const auto* id = std::get_if<protocol::ReadDeviceIdResponse>(&*decoded);
        if (id == nullptr) return std::nullopt;
        std::size_t offset = 0;
        protocol::DeviceIdObject object;
        while (id->next(offset, object))
            seen[object.id] = true;
        if (id->more_follows != kMoreFollows) {
            return basic_from_start ? missing_basic_objects(first, seen) : std::nullopt;
        }
        const std::uint8_t next = id->next_object_id;
        std::vector<std::uint8_t> again = request;
        again[kObjectIdAt] = next;
        if (asked[next]) {
            return Outcome{Verdict::Fail,
                           fmt::format("more follows never ends: answer {} says more follows "
                                       "(FF) from object {:02X}, which was asked for already",
                                       round - 1, next),
                           {first}};
        }
        asked[next] = true;
        client::LinkError error;
        if (!session.send(again, 1, error)) {
            return Outcome{Verdict::Fail, "cannot send: " + error.message, {}};
        }
        Judgement judgement = judge(again, session.receive_frame(timeout), timeout, {});
        Exchange& exchange = judgement.exchange;
        exchange.on_connection = session.connection_requests();
        const auto& got = exchange.received;
        std::optional<std::string> broken;
        if (exchange.status != client::ReceiveStatus::Frame) {
            broken = describe_failure(exchange);
        } else if (got.size() < 9 || !std::equal(got.begin(), got.begin() + 4, again.begin()) ||
                   got[6] != again[6]) {
            broken = "wrong transaction id, protocol id or unit id";
        } else {
            broken = spec_failure(exchange);
        }
        if (broken) {
            return Outcome{Verdict::Fail,
                           fmt::format("device identification answer {} (from object {:02X}, "
                                       "after more follows FF): {}",
                                       round, next, *broken),
                           {exchange}};
        }
        answer = got;
    }
}

// Pipelined answers may come in any order ([TCPG]: the transaction id pairs them); each goes to
// the unanswered step with its transaction id, or else to the first unanswered step.
void collect_answers(Session& session, const std::vector<ResolvedStep>& steps,
                     std::vector<std::optional<client::Received>>& answers) {
    for (std::size_t n = 0; n < steps.size(); ++n) {
        auto received =
            session.receive_frame(steps[n].step->timeout.value_or(session.options().timeout));
        const bool whole = received.status == client::ReceiveStatus::Frame;
        std::optional<std::size_t> slot;
        for (std::size_t i = 0; i < steps.size() && !slot; ++i) {
            if (!answers[i] && whole &&
                transaction_of(steps[i].request) == transaction_of(received.bytes)) {
                slot = i;
            }
        }
        for (std::size_t i = 0; i < steps.size() && !slot; ++i) {
            if (!answers[i]) slot = i;
        }
        answers[*slot] = std::move(received);
        if (!whole) return;
    }
}

}  // namespace

RunResult Engine::run(const std::vector<Suite>& suites, const std::string& target) {
    RunResult result;
    result.target = target;
    result.dut = session_.dut();
    const auto start = Clock::now();
    const std::size_t requests_before = session_.requests();
    for (const auto& suite : suites)
        result.suites.push_back(run_suite(suite));
    result.interrupted = stopped();
    session_.close();
    result.elapsed = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
    result.requests = session_.requests() - requests_before;
    return result;
}

SuiteResult Engine::run_suite(const Suite& suite) {
    SuiteResult result{suite.name, suite.title, suite.file, {}};
    std::map<std::string, Verdict> verdicts;
    if (listener_ != nullptr && !stopped()) listener_->suite_started(suite);
    for (const auto& c : suite.cases) {
        CaseResult case_result{c.id, c.source, c.title, {}, {}, 0, false};
        if (stopped()) {
            // Reports list every case, so a reader sees what an interrupted run left out.
            case_result.outcome = verdict(Verdict::NotRun, "interrupted");
            case_result.interrupted = true;
            result.cases.push_back(std::move(case_result));
            continue;
        }
        const auto start = Clock::now();
        const std::size_t requests_before = session_.requests();
        std::string blocked;
        for (const auto& dependency : c.depends_on) {
            if (verdicts[dependency] != Verdict::Pass) {
                blocked = fmt::format("{} did not pass ({})", dependency,
                                      verdict_label(verdicts[dependency]));
                break;
            }
        }
        case_result.outcome = blocked.empty() ? run_case(c) : verdict(Verdict::NotRun, blocked);
        case_result.elapsed =
            std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
        case_result.requests = session_.requests() - requests_before;
        // The signal may have cut a wait of this case short (a poll returning EINTR), so a
        // failure then is said to have happened under the interruption.
        if (stopped() && case_result.outcome.verdict == Verdict::Fail) {
            case_result.outcome.reason += " (the run was interrupted during this case)";
        }
        verdicts[c.id] = case_result.outcome.verdict;
        if (listener_ != nullptr) listener_->case_finished(suite, case_result);
        result.cases.push_back(std::move(case_result));
    }
    return result;
}

Outcome Engine::run_case(const Case& c) {
    if (auto not_applicable = check_requirements(c, session_.dut())) return *not_applicable;
    const std::size_t requests_before = session_.requests();
    Outcome outcome;
    bool fresh = false;
    if (c.procedure.empty()) {
        outcome = run_steps(c, fresh);
    } else {
        const ProcedureInfo* info = find_procedure(c.procedure);
        if (info == nullptr) return verdict(Verdict::NotRun, "unknown procedure " + c.procedure);
        for (auto need : info->needs) {
            Requirement requirement{std::string(need), "", 0, std::string(need)};
            if (auto why = unmet(requirement, session_.dut())) {
                return verdict(Verdict::NotApplicable, *why);
            }
        }
        if (info->talks_modbus) {
            if (auto unreachable = check_reachable()) return *unreachable;
        }
        outcome = info->run(session_, c);
    }
    // A case that talked to the device is over only when the device has said all it will: bytes
    // nobody asked for (an answer sent twice, noise between cases) fail the case that provoked
    // them here, not the next case that would take them for its answer.
    if (session_.requests() != requests_before && outcome.verdict != Verdict::Fail &&
        outcome.verdict != Verdict::NotRun) {
        auto unasked = session_.take_unasked(session_.options().settle);
        if (!unasked.bytes.empty()) {
            std::vector<std::uint8_t> last = session_.last_frame();
            Outcome failed{Verdict::Fail,
                           describe_unasked(unasked, "after the case's last answer,", last),
                           {unasked_exchange(std::move(unasked), {})}};
            session_.close();
            return failed;
        }
    }
    if (fresh) session_.close();
    return outcome;
}

std::optional<Outcome> Engine::check_reachable() {
    client::LinkError error;
    if (session_.connect(error)) return std::nullopt;
    // The device went away (perhaps an earlier case brought it down): nothing can be judged.
    return verdict(Verdict::NotRun, "cannot connect to the device: " + error.message);
}

Outcome Engine::run_steps(const Case& c, bool& fresh) {
    std::vector<ResolvedStep> steps;
    for (const auto& step : c.steps) {
        ResolvedStep resolved{&step, {}, {}};
        auto request = resolve(step.request, session_.facts());
        if (!request) {
            return verdict(Verdict::NotApplicable,
                           fmt::format("the DUT does not declare {}", request.error().name));
        }
        resolved.request = render_bytes(request.value());
        if (auto why =
                mbap_only_reason(session_, c.pipeline, !step.split.empty(), resolved.request)) {
            return verdict(Verdict::NotApplicable, *why);
        }
        for (const auto& alternative : step.expect) {
            auto pattern = resolve(alternative.pattern, session_.facts());
            if (!pattern) {
                return verdict(Verdict::NotApplicable,
                               fmt::format("the DUT does not declare {}", pattern.error().name));
            }
            resolved.expect.push_back(std::move(pattern.value()));
        }
        steps.push_back(std::move(resolved));
    }
    if (c.isolated) session_.close();
    if (auto unreachable = check_reachable()) return *unreachable;

    client::LinkError error;
    std::vector<std::optional<client::Received>> answers(steps.size());
    if (c.pipeline) {
        std::vector<std::uint8_t> all;
        for (const auto& step : steps) {
            all.insert(all.end(), step.request.begin(), step.request.end());
        }
        if (!session_.send(all, steps.size(), error)) {
            session_.close();
            return verdict(Verdict::Fail, "cannot send: " + error.message);
        }
        collect_answers(session_, steps, answers);
    }

    Outcome outcome;
    std::vector<std::string> remarks;
    bool out_of_step = false;
    std::size_t busy = 0;
    auto fail_step = [&](std::size_t i, std::string reason, Exchange evidence) {
        outcome.verdict = Verdict::Fail;
        outcome.reason = steps.size() > 1
                             ? fmt::format("step {} of {}: {}", i + 1, steps.size(), reason)
                             : std::move(reason);
        outcome.evidence.push_back(std::move(evidence));
    };
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const ResolvedStep& resolved = steps[i];
        const Step& step = *resolved.step;
        if (!c.pipeline &&
            !session_.send(resolved.request, 1, error, step.split, step.split_delay)) {
            // The device hung up while the request was going out (e.g. after part of it).
            client::Received none{client::ReceiveStatus::Closed, {}, error.message};
            fail_step(i, "cannot send: " + error.message,
                      judge(resolved.request, std::move(none), {}, resolved.expect).exchange);
            break;
        }
        const auto waited =
            step.silence ? *step.silence : step.timeout.value_or(session_.options().timeout);
        const std::vector<std::uint8_t> previous_frame = session_.last_frame();
        client::Received received;
        if (c.pipeline) {
            received = answers[i] ? std::move(*answers[i])
                                  : client::Received{client::ReceiveStatus::Timeout, {}, {}};
        } else {
            received = step.silence ? session_.receive_any(waited) : session_.receive_frame(waited);
        }
        const bool closed = received.status == client::ReceiveStatus::Closed;
        Judgement judgement = judge(resolved.request, std::move(received), waited, resolved.expect);
        judgement.exchange.silence_expected = step.silence.has_value();
        judgement.exchange.on_connection = session_.connection_requests();
        const Exchange& exchange = judgement.exchange;
        bool passed = false;
        const bool silent =
            exchange.status == client::ReceiveStatus::Timeout && exchange.received.empty();
        const std::optional<std::string>& tolerated = closed && exchange.received.empty()
                                                          ? step.accept_close
                                                      : silent ? step.accept_silence
                                                               : std::nullopt;
        if (tolerated && !step.silence) {
            passed = true;
            if (!tolerated->empty()) remarks.push_back(*tolerated);
        } else if (step.silence) {
            passed = silent;
        } else if (judgement.matched >= 0) {
            passed = true;
            const auto& remark = step.expect[static_cast<std::size_t>(judgement.matched)].remark;
            if (!remark.empty()) remarks.push_back(remark);
        } else if (c.pipeline &&
                   is_exception(exchange, protocol::ExceptionCode::ServerDeviceBusy) &&
                   std::equal(exchange.received.begin(), exchange.received.begin() + 2,
                              exchange.sent.begin())) {
            // [TCPG]: a server may take fewer outstanding requests than were sent and answer
            // the rest "busy"; that is back-pressure, not a fault.
            passed = true;
            ++busy;
        }
        if (!passed) {
            // An optional function the device does not serve makes the case N/A, whichever
            // step asked for it: 01 is then the right answer.
            if (c.unsupported_is_na &&
                is_exception(exchange, protocol::ExceptionCode::IllegalFunction)) {
                fresh = true;
                return verdict(
                    Verdict::NotApplicable,
                    fmt::format("the device answered exception 01: function {:02X} is not "
                                "supported{}",
                                resolved.request[kPduAt],
                                steps.size() > 1
                                    ? fmt::format(" (step {} of {})", i + 1, steps.size())
                                    : std::string()));
            }
            std::string reason;
            if (exchange.status == client::ReceiveStatus::Frame && !previous_frame.empty() &&
                exchange.received == previous_frame) {
                reason = describe_duplicate(exchange.received);
            } else {
                reason = describe_failure(exchange);
                if (silent && !step.silence) reason += session_.no_answer_hint(resolved.request);
            }
            fail_step(i, std::move(reason), judgement.exchange);
            break;
        }
        // A tolerated close or silence leaves the connection closed or out of step.
        if (tolerated && !step.silence) {
            out_of_step = true;
            break;
        }
        if (step.silence) continue;
        if (auto broken = spec_failure(exchange)) {
            fail_step(i, *broken, judgement.exchange);
            break;
        }
        if (auto stream = follow_device_id_stream(session_, exchange, waited)) {
            fail_step(i, stream->reason,
                      stream->evidence.empty() ? judgement.exchange : stream->evidence.front());
            break;
        }
        // Pipelined answers are all in; otherwise the next request must not meet a leftover.
        if (!c.pipeline && i + 1 < steps.size()) {
            auto unasked = session_.take_unasked(std::chrono::milliseconds(0));
            if (!unasked.bytes.empty()) {
                fail_step(i, describe_unasked(unasked, "after this answer,", exchange.received),
                          unasked_exchange(std::move(unasked), resolved.request));
                break;
            }
        }
    }
    if (outcome.verdict == Verdict::Pass && busy == steps.size()) {
        outcome.verdict = Verdict::Fail;
        outcome.reason = "every pipelined request was answered exception 06 (busy)";
    } else if (busy > 0) {
        remarks.push_back(fmt::format(
            "{} of {} pipelined requests were answered 06 (busy): the device takes fewer "
            "requests at once",
            busy, steps.size()));
    }
    if (outcome.verdict == Verdict::Pass) {
        for (const auto& remark : remarks) {
            outcome.reason += (outcome.reason.empty() ? "" : "; ") + remark;
        }
    }
    // A failed case, or one whose device closed or went out of step, may leave answers in
    // flight: the next case starts afresh. An isolated case is closed by the engine once it has
    // looked for bytes nobody asked for.
    if (outcome.verdict != Verdict::Pass || out_of_step) session_.close();
    fresh = c.isolated;
    return outcome;
}

}  // namespace mblab::conformance
