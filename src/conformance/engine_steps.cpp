#include <fmt/core.h>

#include <algorithm>
#include <map>

#include "client/hex_text.hpp"
#include "conformance/answer_rules.hpp"
#include "conformance/engine.hpp"
#include "conformance/engine_support.hpp"
#include "conformance/judge.hpp"
#include "conformance/plain_requests.hpp"
#include "conformance/procedures.hpp"
#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

using namespace engine_detail;

Outcome Engine::run_steps(const Case& c, bool& fresh) {
    std::vector<ResolvedStep> steps;
    for (const auto& step : c.steps) {
        ResolvedStep resolved{&step, {}, {}};
        auto request = resolve(step.request, session_.facts());
        if (!request) {
            return not_declared(std::string(request.error().name));
        }
        resolved.request = render_bytes(request.value());
        if (auto why =
                mbap_only_reason(session_, c.pipeline, !step.split.empty(), resolved.request)) {
            return verdict(Verdict::NotApplicable, *why);
        }
        for (const auto& alternative : step.expect) {
            auto pattern = resolve(alternative.pattern, session_.facts());
            if (!pattern) {
                return not_declared(std::string(pattern.error().name));
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
        note_served(exchange);
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
                   transaction_of(exchange.received) == transaction_of(exchange.sent)) {
            // [TCPG]: a server may take fewer outstanding requests than were sent and answer
            // the rest "busy"; that is back-pressure, not a fault.
            passed = true;
            ++busy;
        }
        if (!passed) {
            // An optional function the device does not serve makes the case N/A, whichever
            // step asked for it: 01 is then the right answer.
            // Exception 01 is only right when the function is not served at all: a device that
            // serves it and answers 01 to a request it should refuse otherwise (a quantity of 0,
            // say: [APP] asks 03) fails.
            const auto asked = pdu_of(resolved.request);
            const std::uint8_t function = asked.front();
            const std::string at_step = steps.size() > 1
                                            ? fmt::format(" (step {} of {})", i + 1, steps.size())
                                            : std::string();
            if (c.unsupported_is_na &&
                is_exception(exchange, protocol::ExceptionCode::IllegalFunction)) {
                Exchange failed = judgement.exchange;
                const auto key = service_key(pdu_of(resolved.request));
                const bool seen = key && served_.contains(*key);
                auto served = served_anyway(pdu_of(resolved.request));
                if (!served) {
                    fresh = true;
                    return verdict(Verdict::NotApplicable,
                                   fmt::format("the device answered exception 01: function {:02X} "
                                               "is not supported{}{}",
                                               function, at_step, role_hint(session_, asked)));
                }
                fail_step(i,
                          fmt::format("exception 01 (illegal function), yet the device serves "
                                      "{} ({}): 01 says a function is not served{}",
                                      service_name(asked),
                                      seen ? "it answered it otherwise earlier in this run"
                                           : "its plain request was answered " +
                                                 client::hex_bytes(served->received),
                                      role_hint(session_, asked)),
                          std::move(failed));
                break;
            }
            // Individual access to device identification (read code 04) is optional: a device
            // whose conformity level says stream access only answers it 03 ([APP] 6.21).
            if (c.unsupported_is_na && asked.size() == 4 && asked[0] == kEncapsulated &&
                asked[1] == kMeiReadDeviceId && asked[kReadCodeAt] == 0x04 &&
                is_exception(exchange, protocol::ExceptionCode::IllegalDataValue)) {
                if (auto level = stream_access_only()) {
                    fresh = true;
                    return verdict(Verdict::NotApplicable,
                                   fmt::format("the device answered exception 03 to individual "
                                               "access, and its conformity level {:02X} declares "
                                               "stream access only{}",
                                               *level, at_step));
                }
            }
            std::string reason;
            if (exchange.status == client::ReceiveStatus::Frame && !previous_frame.empty() &&
                exchange.received == previous_frame) {
                reason = describe_duplicate(exchange.received);
            } else {
                reason = describe_failure(exchange, session_.framing());
                if (silent && !step.silence) reason += session_.no_answer_hint(resolved.request);
                // 01 where the case's document asks for an answer: a function the device lacks,
                // which that section requires (unless the device serves it after all).
                if (is_exception(exchange, protocol::ExceptionCode::IllegalFunction)) {
                    if (!served_anyway(asked)) {
                        reason += fmt::format(": the device does not serve {}, which {} requires",
                                              service_name(asked), c.source);
                    }
                    reason += role_hint(session_, asked);
                }
            }
            fail_step(i, std::move(reason), judgement.exchange);
            break;
        }
        // A tolerated close or silence leaves the connection closed or out of step; the device
        // must still serve others, or a close that was a crash would pass.
        if (tolerated && !step.silence) {
            out_of_step = true;
            if (auto dead = no_longer_serves()) {
                const std::string allowed = tolerated->empty()
                                                ? std::string(
                                                      "the device closed or fell silent, as the "
                                                      "case allows")
                                                : *tolerated;
                fail_step(i, allowed + ", but " + *dead, judgement.exchange);
            }
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
