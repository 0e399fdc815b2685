#include "conformance/engine.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>

#include "conformance/answer_rules.hpp"
#include "conformance/judge.hpp"
#include "conformance/plain_requests.hpp"
#include "conformance/procedures.hpp"
#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/mbap_header.hpp"
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

bool is_exception(const Exchange& exchange, protocol::ExceptionCode code) {
    return exchange.status == client::ReceiveStatus::Frame &&
           is_exception_answer(exchange.sent, exchange.received, code);
}

// The PDU of a request or answer in the catalogue's notation (an MBAP frame); empty when there is
// none.
std::span<const std::uint8_t> pdu_of(std::span<const std::uint8_t> adu) {
    const auto frame = protocol::read_mbap_frame(adu);
    return frame ? frame->pdu : std::span<const std::uint8_t>{};
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
// In a 2B / 0E request PDU: function, MEI type, read device id code, object id.
constexpr std::size_t kReadCodeAt = 2;
constexpr std::size_t kObjectIdAt = 3;

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
    const auto request_frame = protocol::read_mbap_frame(request);
    if (!request_frame) return std::nullopt;
    const auto asked_pdu = request_frame->pdu;
    if (asked_pdu.size() != 4 || asked_pdu[0] != kEncapsulated ||
        asked_pdu[1] != kMeiReadDeviceId || asked_pdu[kReadCodeAt] < 1 ||
        asked_pdu[kReadCodeAt] > 3) {
        return std::nullopt;
    }
    const bool basic_from_start = asked_pdu[kReadCodeAt] == 1 && asked_pdu[kObjectIdAt] == 0;
    // Where the object id sits in the request as the catalogue writes it.
    const std::size_t object_id_at = request.size() - asked_pdu.size() + kObjectIdAt;
    std::vector<std::uint8_t> answer = first.received;
    std::vector<bool> asked(256, false);
    std::vector<bool> seen(256, false);
    asked[asked_pdu[kObjectIdAt]] = true;
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
        again[object_id_at] = next;
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
        const auto got_frame = protocol::read_mbap_frame(got);
        const auto& asked_header = request_frame->header;
        std::optional<std::string> broken;
        if (exchange.status != client::ReceiveStatus::Frame) {
            broken = describe_failure(exchange);
        } else if (!got_frame || got_frame->pdu.size() < 2 ||
                   got_frame->header.transaction_id != asked_header.transaction_id ||
                   got_frame->header.protocol_id != asked_header.protocol_id ||
                   got_frame->header.unit != asked_header.unit) {
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
    result.unanswered = unanswered_;
    session_.close();
    result.elapsed = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
    result.requests = session_.requests() - requests_before;
    return result;
}

SuiteResult Engine::run_suite(const Suite& suite) {
    SuiteResult result{suite.name, suite.title, suite.file, {}};
    std::map<std::string, Verdict> verdicts;
    if (listener_ != nullptr && !stopped() && unanswered_.empty()) listener_->suite_started(suite);
    for (const auto& c : suite.cases) {
        CaseResult case_result{c.id, c.source, c.title, {}, {}, 0, false};
        if (!unanswered_.empty()) {
            case_result.outcome = verdict(Verdict::NotRun, "the device answered nothing");
            result.cases.push_back(std::move(case_result));
            continue;
        }
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
        if (stop_if_unanswered_ && session_.probed() && !session_.heard()) {
            const bool tcp = session_.framing() == client::Framing::Mbap;
            unanswered_ =
                fmt::format("no answer on {} {}{} to {} requests: check the port and --unit",
                            tcp ? "unit" : "address", session_.dut().unit, tcp ? ", 255 or 0" : "",
                            session_.requests());
        }
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
    if (session_.ever_connected() && session_.reconnect(error)) return std::nullopt;
    // A device that took connections earlier in the run and refuses them now has stopped serving
    // (an earlier case may have brought it down): that is a failure, not a case left unjudged,
    // or a run against a dead device would end with nothing failed.
    if (session_.ever_connected()) {
        return verdict(Verdict::Fail,
                       "the device no longer accepts connections (it did earlier in the run): " +
                           error.message);
    }
    return verdict(Verdict::NotRun, "cannot connect to the device: " + error.message);
}

Exchange Engine::ask(std::vector<std::uint8_t> pdu) {
    constexpr std::uint16_t kProbeTransaction = 0x7E57;
    std::vector<std::uint8_t> request(protocol::adu_size(protocol::Framing::Mbap, pdu.size()));
    protocol::write_adu({protocol::Framing::Mbap, session_.dut().unit, kProbeTransaction, 0}, pdu,
                        request);
    client::LinkError error;
    if (!session_.send(request, 1, error)) {
        client::Received none{client::ReceiveStatus::Closed, {}, error.message};
        return judge(request, std::move(none), {}, {}).exchange;
    }
    const auto waited = session_.options().timeout;
    Exchange exchange = judge(request, session_.receive_frame(waited), waited, {}).exchange;
    exchange.on_connection = session_.connection_requests();
    return exchange;
}

std::optional<std::string> Engine::no_longer_serves() {
    session_.close();
    client::LinkError error;
    if (!session_.reconnect(error)) {
        return "afterwards the device refused a new connection: " + error.message;
    }
    // Any whole answer shows the device alive, an exception as well as data: the read of 7.5.1.
    Exchange e = ask({0x03, 0x00, 0x00, 0x00, 0x01});
    session_.close();
    if (e.status == client::ReceiveStatus::Frame) return std::nullopt;
    return "afterwards a plain read (FC 03, 1 register at 0) on a new connection got " +
           describe_failure(e);
}

namespace {

// What exception 01 says is not served, for a request PDU: the function code, and for FC 08 its
// sub-function, for FC 2B its MEI type, which [APP] also refuses with 01 when they are not
// served (an unknown diagnostic sub-function is 01 from a device that serves FC 08).
std::optional<std::uint32_t> service_key(std::span<const std::uint8_t> pdu) {
    constexpr std::uint8_t kDiagnostics = 0x08;
    if (pdu.empty()) return std::nullopt;
    const std::uint32_t function = std::uint32_t{pdu[0]} << 16;
    if (pdu[0] == kDiagnostics) {
        if (pdu.size() < 3) return std::nullopt;
        return function | (std::uint32_t{pdu[1]} << 8) | pdu[2];
    }
    if (pdu[0] == kEncapsulated) {
        if (pdu.size() < 2) return std::nullopt;
        return function | pdu[1];
    }
    return function;
}

// "function 03", "function 08 sub-function 0002", "function 2B MEI type 0E".
std::string service_name(std::span<const std::uint8_t> pdu) {
    if (pdu[0] == 0x08 && pdu.size() >= 3) {
        return fmt::format("function 08 sub-function {:02X}{:02X}", pdu[1], pdu[2]);
    }
    if (pdu[0] == kEncapsulated && pdu.size() >= 2) {
        return fmt::format("function 2B MEI type {:02X}", pdu[1]);
    }
    return fmt::format("function {:02X}", pdu[0]);
}

}  // namespace

void Engine::note_served(const Exchange& exchange) {
    if (exchange.status != client::ReceiveStatus::Frame) return;
    const auto asked = pdu_of(exchange.sent);
    const auto got = pdu_of(exchange.received);
    if (asked.empty() || got.empty() || (got[0] & 0x7F) != asked[0]) return;
    if (exception_answer(exchange.sent, exchange.received) ==
        protocol::ExceptionCode::IllegalFunction) {
        return;
    }
    if (auto key = service_key(asked)) served_.insert(*key);
}

std::optional<Exchange> Engine::served_anyway(std::span<const std::uint8_t> request_pdu) {
    const auto key = service_key(request_pdu);
    if (!key) return std::nullopt;
    if (served_.contains(*key)) return Exchange{};
    // The plain request asks the same service only for some requests (not another diagnostic
    // sub-function, say); only then does its answer say anything.
    auto plain = plain_request_pdu(request_pdu[0]);
    if (!plain || service_key(*plain) != key) return std::nullopt;
    // On a connection of its own: answers of the case may still be on their way on this one.
    session_.close();
    // A write is asked as a write of what is there already, so that asking changes nothing; when
    // what is there cannot be read, as a write the device must refuse with 03.
    if (auto read = read_before_write_back(request_pdu[0])) {
        Exchange now = ask(*read);
        auto back = now.status == client::ReceiveStatus::Frame
                        ? write_back_pdu(request_pdu[0], pdu_of(now.received))
                        : std::nullopt;
        plain = back ? back : harmless_request_pdu(request_pdu[0]);
    } else {
        plain = harmless_request_pdu(request_pdu[0]);
    }
    Exchange e = ask(*plain);
    note_served(e);
    if (!served_.contains(*key)) return std::nullopt;
    return e;
}

std::optional<std::uint8_t> Engine::stream_access_only() {
    constexpr std::uint8_t kIndividualAccess = 0x80;
    session_.close();
    Exchange e = ask({kEncapsulated, kMeiReadDeviceId, 0x01, 0x00});
    auto decoded = protocol::decode_response(pdu_of(e.received));
    if (e.status != client::ReceiveStatus::Frame || !decoded) return std::nullopt;
    const auto* id = std::get_if<protocol::ReadDeviceIdResponse>(&*decoded);
    if (id == nullptr || (id->conformity_level & kIndividualAccess) != 0) return std::nullopt;
    return id->conformity_level;
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
            const std::uint8_t function = pdu_of(resolved.request).front();
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
                                               "is not supported{}",
                                               function, at_step));
                }
                fail_step(i,
                          fmt::format("exception 01 (illegal function), yet the device serves "
                                      "{} ({}): 01 says a function is not served",
                                      service_name(pdu_of(resolved.request)),
                                      seen ? "it answered it otherwise earlier in this run"
                                           : "its plain request was answered " +
                                                 hex_text(served->received)),
                          std::move(failed));
                break;
            }
            // Individual access to device identification (read code 04) is optional: a device
            // whose conformity level says stream access only answers it 03 ([APP] 6.21).
            const auto asked = pdu_of(resolved.request);
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
                reason = describe_failure(exchange);
                if (silent && !step.silence) reason += session_.no_answer_hint(resolved.request);
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
