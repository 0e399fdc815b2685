#include "conformance/judge.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>

#include "client/hex_text.hpp"
#include "client/tls_sniff.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/request_template.hpp"

namespace mblab::conformance {

namespace {

// Fields by byte position in an MBAP frame, to name what differs. Past the function code the
// name comes from the answer fields of the function's request template ([APP] 6).
std::string_view field_at(std::size_t position, int function) {
    if (position < 2) return "transaction id";
    if (position < 4) return "protocol id";
    if (position < 6) return "length field";
    if (position == 6) return "unit id";
    if (position == 7) return "function code";
    if (function < 0) return "data";
    if ((function & protocol::kExceptionBit) != 0) return "exception code";
    const std::size_t at = position - protocol::limits::kMbapHeader;  // in the PDU
    const auto* request = protocol::find_template(static_cast<std::uint8_t>(function));
    if (request == nullptr) return at == 1 ? "byte count" : "data";
    for (const protocol::AnswerField& field : request->answer) {
        if (at >= field.offset && at < std::size_t{field.offset} + field.width) return field.name;
    }
    return request->answer_rest;
}

}  // namespace

std::uint16_t transaction_of(std::span<const std::uint8_t> adu) {
    const auto frame = protocol::read_mbap_frame(adu);
    return frame ? frame->header.transaction_id : 0;
}

std::optional<protocol::ExceptionCode> exception_answer(std::span<const std::uint8_t> request,
                                                        std::span<const std::uint8_t> answer) {
    const auto asked = protocol::read_mbap_frame(request);
    const auto got = protocol::read_mbap_frame(answer);
    if (!asked || !got || asked->pdu.empty() || got->pdu.size() != 2 ||
        got->pdu[0] != (asked->pdu[0] | protocol::kExceptionBit)) {
        return std::nullopt;
    }
    return static_cast<protocol::ExceptionCode>(got->pdu[1]);
}

bool is_exception_answer(std::span<const std::uint8_t> request, std::span<const std::uint8_t> frame,
                         protocol::ExceptionCode code) {
    return exception_answer(request, frame) == code;
}

std::string describe_unasked(const client::Received& got, std::string_view when,
                             std::span<const std::uint8_t> last_frame) {
    const std::size_t total = got.bytes.size() + got.discarded;
    std::string shown =
        client::hex_bytes(std::span(got.bytes).first(std::min<std::size_t>(got.bytes.size(), 32)));
    if (total > 32) shown += fmt::format(" ... ({} bytes in all)", total);
    const bool again =
        got.discarded == 0 && !last_frame.empty() &&
        std::equal(got.bytes.begin(), got.bytes.end(), last_frame.begin(), last_frame.end());
    if (again) {
        return fmt::format(
            "duplicate answer: {} the device sent its last answer a second time, unasked ({})",
            when, shown);
    }
    return fmt::format(
        "unsolicited bytes: {} the device sent {} bytes nobody asked for (an unsolicited or "
        "duplicate answer): {}",
        when, total, shown);
}

Exchange unasked_exchange(client::Received got, std::span<const std::uint8_t> last_request) {
    Exchange exchange;
    exchange.sent.assign(last_request.begin(), last_request.end());
    exchange.status = got.status;
    exchange.received = std::move(got.bytes);
    exchange.discarded = got.discarded;
    exchange.detail = std::move(got.detail);
    exchange.silence_expected = true;
    return exchange;
}

std::string describe_duplicate(std::span<const std::uint8_t> frame) {
    return fmt::format(
        "duplicate answer: instead of an answer to this request came a second copy of the answer "
        "before it ({}): the device answered one request twice",
        client::hex_bytes(frame));
}

Judgement judge(std::span<const std::uint8_t> sent, client::Received received,
                std::chrono::milliseconds waited,
                const std::vector<ResolvedPattern>& alternatives) {
    Judgement out;
    out.exchange.sent.assign(sent.begin(), sent.end());
    out.exchange.status = received.status;
    out.exchange.received = std::move(received.bytes);
    out.exchange.detail = std::move(received.detail);
    out.exchange.discarded = received.discarded;
    out.exchange.waited = waited;
    std::size_t best_differs = SIZE_MAX;
    for (std::size_t i = 0; i < alternatives.size(); ++i) {
        MatchResult result = match(alternatives[i], out.exchange.received);
        const bool whole = out.exchange.status == client::ReceiveStatus::Frame;
        if (whole && result.matched) {
            out.matched = static_cast<int>(i);
            out.exchange.expected = to_text(alternatives[i]);
            out.exchange.match = std::move(result);
            return out;
        }
        if (result.differs.size() < best_differs) {
            best_differs = result.differs.size();
            out.exchange.expected = to_text(alternatives[i]);
            out.exchange.match = std::move(result);
        }
    }
    return out;
}

namespace {

// " from unit 1", when the request names one.
std::string from_unit(const Exchange& exchange) {
    const auto sent = protocol::read_mbap_frame(exchange.sent);
    if (!sent) return {};
    return fmt::format(" from unit {}", sent->header.unit);
}

// " (request 57 on this connection)": a device that stops after N requests shows here.
std::string connection_count(const Exchange& exchange) {
    if (exchange.on_connection == 0) return {};
    return fmt::format(" (request {} on this connection)", exchange.on_connection);
}

constexpr std::size_t kHeaderCells = 7;

// Byte `i` of the expected PDU when the pattern fixes it (not XX, not a computed length).
std::optional<std::uint8_t> expected_pdu_byte(const std::vector<std::string>& cells,
                                              std::size_t i) {
    if (cells.size() <= kHeaderCells + i) return std::nullopt;
    const std::string& cell = cells[kHeaderCells + i];
    if (cell.size() != 2 || !std::isxdigit(static_cast<unsigned char>(cell[0])) ||
        !std::isxdigit(static_cast<unsigned char>(cell[1]))) {
        return std::nullopt;
    }
    return static_cast<std::uint8_t>(std::stoul(cell, nullptr, 16));
}

// "; also wrong transaction id" when the MBAP header differs as well; the length field differs
// with the kind of answer and is not named.
std::string header_faults(const Exchange& exchange, client::Framing carried) {
    constexpr std::size_t kLengthField = 4;
    std::string text;
    if (carried != client::Framing::Mbap) return text;
    for (std::size_t position : exchange.match.differs) {
        if (position >= kHeaderCells || position >= exchange.received.size()) continue;
        if (position == kLengthField || position == kLengthField + 1) continue;
        const auto name = field_at(position, -1);
        if (text.find(name) != std::string::npos) continue;
        text += (text.empty() ? "; also wrong " : ", ") + std::string(name);
    }
    return text;
}

}  // namespace

std::string describe_failure(const Exchange& exchange, client::Framing carried) {
    // A TLS server reached over plain TCP: the link's one line says what to do.
    if (client::is_tls_answer_text(exchange.detail)) return exchange.detail;
    const auto& got = exchange.received;
    switch (exchange.status) {
        case client::ReceiveStatus::Timeout:
            if (exchange.silence_expected) break;
            return got.empty()
                       ? fmt::format("no answer{}: timeout after {} ms{}", from_unit(exchange),
                                     exchange.waited.count(), connection_count(exchange))
                       : fmt::format("incomplete answer ({} bytes): timeout after {} ms{}",
                                     got.size(), exchange.waited.count(),
                                     connection_count(exchange));
        case client::ReceiveStatus::Closed:
            return got.empty() ? fmt::format("no answer{}: {}{}", from_unit(exchange),
                                             exchange.detail, connection_count(exchange))
                               : fmt::format("incomplete answer ({} bytes): {}{}", got.size(),
                                             exchange.detail, connection_count(exchange));
        case client::ReceiveStatus::Malformed:
            return fmt::format("malformed answer: {}", exchange.detail);
        case client::ReceiveStatus::Frame:
            break;
    }
    if (exchange.silence_expected) {
        return got.empty() ? std::string("the device was to stay silent")
                           : fmt::format("the device sent {} bytes when silence was expected",
                                         got.size() + exchange.discarded);
    }
    // An answer of the wrong kind (data where an exception was due, or the converse) is said in
    // those words: the fields that differ between the two kinds say nothing more. The expected
    // pattern is in the catalogue's notation, an MBAP frame: its PDU starts after the 7 cells of
    // the header.
    const auto answer = protocol::read_mbap_frame(got);
    const std::span<const std::uint8_t> pdu =
        answer ? answer->pdu : std::span<const std::uint8_t>{};
    const auto asked = protocol::read_mbap_frame(exchange.sent);
    const int function = asked && !asked->pdu.empty() ? asked->pdu[0] : -1;
    const auto wanted = expected_pdu_byte(exchange.match.expected_cells, 0);
    const bool exception_expected = wanted && (*wanted & protocol::kExceptionBit) != 0;
    if (!pdu.empty() && function >= 0 && pdu[0] == function && exception_expected &&
        *wanted == (function | protocol::kExceptionBit)) {
        const auto code = expected_pdu_byte(exchange.match.expected_cells, 1);
        return (code ? fmt::format(
                           "answered with data where exception {:02X} ({}) was expected", *code,
                           protocol::exception_name(static_cast<protocol::ExceptionCode>(*code)))
                     : std::string("answered with data where an exception was expected")) +
               header_faults(exchange, carried);
    }
    if (pdu.size() == 2 && (pdu[0] & protocol::kExceptionBit) != 0) {
        auto code = static_cast<protocol::ExceptionCode>(pdu[1]);
        std::string text =
            fmt::format("exception {:02X} ({})", pdu[1], protocol::exception_name(code));
        if (wanted && *wanted == function && pdu[0] == (function | protocol::kExceptionBit)) {
            return text + " where data was expected" + header_faults(exchange, carried);
        }
        if (!exception_expected) return text;
        const auto code_wanted = expected_pdu_byte(exchange.match.expected_cells, 1);
        if (code_wanted && exchange.match.differs.size() == 1 &&
            exchange.match.differs.front() == kHeaderCells + 1) {
            return fmt::format("{} instead of {:02X}", text, *code_wanted);
        }
    }
    std::vector<std::string_view> fields;
    const int answered = pdu.empty() ? -1 : pdu[0];
    // On a line the tester laid out the transaction id, protocol id and length from the
    // request and the answer's size: only the address and what follows came from the device.
    constexpr std::size_t kUnitAt = 6;
    for (std::size_t position : exchange.match.differs) {
        if (carried != client::Framing::Mbap && position < kUnitAt) continue;
        auto name = position < got.size() ? field_at(position, answered)
                                          : std::string_view("missing bytes");
        if (std::find(fields.begin(), fields.end(), name) == fields.end()) fields.push_back(name);
    }
    if (fields.empty()) return "wrong answer length";
    if (fields.size() == 1 && fields.front() == "missing bytes") {
        return fmt::format("the answer is too short: {} bytes where at least {} were expected",
                           got.size(), exchange.match.expected_cells.size());
    }
    std::string text = "wrong ";
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i) text += ", ";
        text += fields[i];
    }
    return text;
}

}  // namespace mblab::conformance
