#include "conformance/engine.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>

#include "conformance/answer_rules.hpp"
#include "conformance/engine_support.hpp"
#include "conformance/judge.hpp"
#include "conformance/line_evidence.hpp"
#include "conformance/plain_requests.hpp"
#include "conformance/procedures.hpp"
#include "conformance/serving_check.hpp"
#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

namespace {

using namespace engine_detail;
using Clock = std::chrono::steady_clock;

// The transaction id of the tester's own requests between a case's steps.
constexpr std::uint16_t kProbeTransaction = 0x7E57;

// The session as a link for the serving check: requests in the catalogue's notation, answers
// handed back in it, whatever the framing underneath.
struct SessionLink {
    Session& session;
    bool send(std::span<const std::uint8_t> bytes, client::LinkError& error) {
        return session.send(bytes, 1, error);
    }
    client::Received receive_frame(std::chrono::milliseconds timeout) {
        return session.receive_frame(timeout);
    }
};

std::optional<Outcome> check_requirements(const Case& c, const Dut& dut) {
    for (const auto& requirement : c.requirements) {
        if (auto why = unmet(requirement, dut)) return not_met(*why);
    }
    return std::nullopt;
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
        // A case that does not apply is N/A whatever became of the cases it depends on.
        if (!blocked.empty()) {
            if (auto not_applicable = check_requirements(c, session_.dut())) blocked.clear();
        }
        session_.start_case(c.id);
        case_result.outcome = blocked.empty() ? run_case(c) : verdict(Verdict::NotRun, blocked);
        // Judged in the catalogue's notation; shown as the line carried it.
        for (auto& exchange : case_result.outcome.evidence)
            show_as_on_line(exchange, session_.framing(), session_.line_frames());
        session_.end_case();
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
            if (auto why = unmet(requirement, session_.dut())) return not_met(*why);
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
    SessionLink link{session_};
    const auto timeout = session_.options().timeout;
    const auto answer = ask_serving(
        link, {.header = {protocol::Framing::Mbap, session_.dut().unit, kProbeTransaction, 0},
               .timeout = timeout,
               .any_answer = true});
    Exchange e = answer.exchange(timeout);
    e.on_connection = session_.connection_requests();
    session_.close();
    if (answer.served == Served::Yes) return std::nullopt;
    return "afterwards a plain read (FC 03, 1 register at 0) on a new connection got " +
           describe_failure(e, session_.framing());
}

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

}  // namespace mblab::conformance
