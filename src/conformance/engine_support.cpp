#include "conformance/engine_support.hpp"

#include <fmt/core.h>

#include "conformance/answer_rules.hpp"
#include "conformance/judge.hpp"
#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_table.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance::engine_detail {

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

constexpr std::uint8_t kMoreFollows = 0xFF;
constexpr std::size_t kObjectIdAt = 3;

namespace {

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

}  // namespace

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
            broken = describe_failure(exchange, session.framing());
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

std::string role_hint(const Session& session, std::span<const std::uint8_t> pdu) {
    const std::string& role = session.certificate_role();
    if (role.empty() || pdu.empty()) return {};
    // A role may read and still not use every reading function: only writes are named as such.
    const auto* row = protocol::find_function(pdu[0]);
    const std::string what = row != nullptr && row->writes == protocol::Writes::Yes
                                 ? std::string("write")
                                 : fmt::format("use function {:02X}", pdu[0]);
    return fmt::format(", or the certificate's role {} may not {} ([SEC] R-31)", role, what);
}

}  // namespace mblab::conformance::engine_detail
