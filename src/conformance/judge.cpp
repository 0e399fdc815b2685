#include "conformance/judge.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

namespace mblab::conformance {

namespace {

// MBAP fields by byte position, to name what differs.
std::string_view field_at(std::size_t position) {
    if (position < 2) return "transaction id";
    if (position < 4) return "protocol id";
    if (position < 6) return "length field";
    if (position == 6) return "unit id";
    if (position == 7) return "function code";
    return "data";
}

}  // namespace

Judgement judge(std::span<const std::uint8_t> sent, client::Received received,
                std::chrono::milliseconds waited,
                const std::vector<ResolvedPattern>& alternatives) {
    Judgement out;
    out.exchange.sent.assign(sent.begin(), sent.end());
    out.exchange.status = received.status;
    out.exchange.received = std::move(received.bytes);
    out.exchange.detail = std::move(received.detail);
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

std::string describe_failure(const Exchange& exchange) {
    const auto& got = exchange.received;
    switch (exchange.status) {
        case client::ReceiveStatus::Timeout:
            if (exchange.silence_expected) break;
            return got.empty()
                       ? fmt::format("no answer: timeout after {} ms", exchange.waited.count())
                       : fmt::format("incomplete answer ({} bytes): timeout after {} ms",
                                     got.size(), exchange.waited.count());
        case client::ReceiveStatus::Closed:
            return got.empty() ? fmt::format("no answer: {}", exchange.detail)
                               : fmt::format("incomplete answer ({} bytes): {}", got.size(),
                                             exchange.detail);
        case client::ReceiveStatus::Malformed:
            return fmt::format("malformed answer: {}", exchange.detail);
        case client::ReceiveStatus::Frame:
            break;
    }
    if (exchange.silence_expected) {
        return got.empty()
                   ? std::string("the device was to stay silent")
                   : fmt::format("the device was to stay silent but sent {} bytes", got.size());
    }
    // An exception answer to a request that expected data is the most common failure: name it.
    const auto& cells = exchange.match.expected_cells;
    const bool expected_exception = cells.size() > 7 && cells[7] != "XX" && cells[7][0] >= '8';
    if (got.size() == 9 && (got[7] & protocol::kExceptionBit) != 0) {
        auto code = static_cast<protocol::ExceptionCode>(got[8]);
        std::string text =
            fmt::format("exception {:02X} ({})", got[8], protocol::exception_name(code));
        if (!expected_exception) return text;
        if (cells.size() > 8 && cells[8] != "XX" && exchange.match.differs.size() == 1 &&
            exchange.match.differs.front() == 8) {
            return text + " instead of " + cells[8];
        }
    }
    std::vector<std::string_view> fields;
    for (std::size_t position : exchange.match.differs) {
        auto name = position < got.size() ? field_at(position) : std::string_view("missing bytes");
        if (std::find(fields.begin(), fields.end(), name) == fields.end()) fields.push_back(name);
    }
    std::string text = "wrong ";
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i) text += ", ";
        text += fields[i];
    }
    return text;
}

}  // namespace mblab::conformance
