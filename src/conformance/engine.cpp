#include "conformance/engine.hpp"

#include <fmt/core.h>

#include <map>

#include "conformance/judge.hpp"
#include "conformance/procedures.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

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

// True when the device answered "illegal function" to the request's function code.
bool is_illegal_function(const Exchange& exchange) {
    const auto& got = exchange.received;
    return exchange.status == client::ReceiveStatus::Frame && got.size() == 9 &&
           exchange.sent.size() > 7 && got[7] == (exchange.sent[7] | protocol::kExceptionBit) &&
           got[8] == static_cast<std::uint8_t>(protocol::ExceptionCode::IllegalFunction);
}

// The transaction id of a request or answer.
std::uint16_t transaction_of(std::span<const std::uint8_t> adu) {
    return adu.size() >= 2 ? static_cast<std::uint16_t>(adu[0] << 8 | adu[1]) : 0;
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
    session_.close();
    result.elapsed = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
    result.requests = session_.requests() - requests_before;
    return result;
}

SuiteResult Engine::run_suite(const Suite& suite) {
    SuiteResult result{suite.name, suite.title, suite.file, {}};
    std::map<std::string, Verdict> verdicts;
    if (listener_ != nullptr) listener_->suite_started(suite);
    for (const auto& c : suite.cases) {
        CaseResult case_result{c.id, c.source, c.title, {}, {}, 0};
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
        verdicts[c.id] = case_result.outcome.verdict;
        if (listener_ != nullptr) listener_->case_finished(suite, case_result);
        result.cases.push_back(std::move(case_result));
    }
    return result;
}

Outcome Engine::run_case(const Case& c) {
    if (auto not_applicable = check_requirements(c, session_.dut())) return *not_applicable;
    if (c.procedure.empty()) return run_steps(c);
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
    return info->run(session_, c);
}

std::optional<Outcome> Engine::check_reachable() {
    client::LinkError error;
    if (session_.connect(error)) return std::nullopt;
    // The device went away (perhaps an earlier case brought it down): nothing can be judged.
    return verdict(Verdict::NotRun, "cannot connect to the device: " + error.message);
}

Outcome Engine::run_steps(const Case& c) {
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
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const ResolvedStep& resolved = steps[i];
        const Step& step = *resolved.step;
        if (!c.pipeline &&
            !session_.send(resolved.request, 1, error, step.split, step.split_delay)) {
            // The device hung up while the request was going out (e.g. after part of it).
            client::Received none{client::ReceiveStatus::Closed, {}, error.message};
            outcome.verdict = Verdict::Fail;
            outcome.reason = "cannot send: " + error.message;
            outcome.evidence.push_back(
                judge(resolved.request, std::move(none), {}, resolved.expect).exchange);
            break;
        }
        const auto waited =
            step.silence ? *step.silence : step.timeout.value_or(session_.options().timeout);
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
        const Exchange& exchange = judgement.exchange;
        if (i == 0 && c.unsupported_is_na && is_illegal_function(exchange)) {
            session_.close();
            return verdict(Verdict::NotApplicable,
                           fmt::format("the device answered exception 01: function {:02X} is "
                                       "not supported",
                                       resolved.request[7]));
        }
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
        }
        if (!passed) {
            outcome.verdict = Verdict::Fail;
            outcome.reason = describe_failure(exchange);
            if (steps.size() > 1) {
                outcome.reason =
                    fmt::format("step {} of {}: {}", i + 1, steps.size(), outcome.reason);
            }
            outcome.evidence.push_back(judgement.exchange);
            break;
        }
        // A tolerated close or silence leaves the connection closed or out of step.
        if (tolerated && !step.silence) {
            out_of_step = true;
            break;
        }
    }
    if (outcome.verdict == Verdict::Pass) {
        for (const auto& remark : remarks) {
            outcome.reason += (outcome.reason.empty() ? "" : "; ") + remark;
        }
    }
    // A failed or isolated case may leave answers in flight; start the next case afresh.
    if (outcome.verdict != Verdict::Pass || c.isolated || out_of_step) session_.close();
    return outcome;
}

}  // namespace mblab::conformance
