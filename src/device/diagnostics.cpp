#include "device/diagnostics.hpp"

#include <algorithm>

#include "support/name_table.hpp"

namespace mblab::device {

namespace {

using protocol::DiagnosticSub;
using protocol::ExceptionCode;

constexpr auto kFc = static_cast<std::uint8_t>(protocol::FunctionCode::Diagnostics);

MaybeResponse answer(std::uint16_t sub, std::span<const std::uint8_t> data) {
    return protocol::Response{protocol::DiagnosticsResponse{sub, data}};
}

MaybeResponse answer_word(std::uint16_t sub, std::uint16_t value, std::span<std::uint8_t> scratch) {
    scratch[0] = static_cast<std::uint8_t>(value >> 8);
    scratch[1] = static_cast<std::uint8_t>(value & 0xFF);
    return answer(sub, scratch.first(2));
}

bool is_word(std::span<const std::uint8_t> data, std::uint16_t value) {
    return data.size() == 2 && data[0] == (value >> 8) && data[1] == (value & 0xFF);
}

// The counter that each "return ... count" sub-function reads.
struct CounterRow {
    DiagnosticSub value;
    std::uint16_t CommCounters::*counter;
};

constexpr CounterRow kCounters[] = {
    {DiagnosticSub::BusMessageCount, &CommCounters::bus_messages},
    {DiagnosticSub::BusCommunicationErrorCount, &CommCounters::bus_errors},
    {DiagnosticSub::BusExceptionErrorCount, &CommCounters::bus_exceptions},
    {DiagnosticSub::ServerMessageCount, &CommCounters::server_messages},
    {DiagnosticSub::ServerNoResponseCount, &CommCounters::no_response},
    {DiagnosticSub::ServerNakCount, &CommCounters::naks},
    {DiagnosticSub::ServerBusyCount, &CommCounters::busy},
    {DiagnosticSub::BusCharacterOverrunCount, &CommCounters::overruns},
};

std::uint16_t counter(const CommCounters& c, DiagnosticSub sub) {
    const CounterRow* row = row_of(kCounters, sub);
    return row != nullptr ? c.*(row->counter) : 0;
}

MaybeResponse echo(const protocol::DiagnosticsRequest& request, const DiagnosticsSpec& spec) {
    if (spec.echo_min_words || spec.echo_max_words) {
        const std::size_t words = request.data.size() / 2;
        if (request.data.size() % 2 != 0 || words < spec.echo_min_words.value_or(0) ||
            words > spec.echo_max_words.value_or(125)) {
            return exception_response(kFc, ExceptionCode::IllegalDataValue);
        }
    }
    return answer(request.sub_function, request.data);
}

}  // namespace

bool resets_event_counter(std::uint16_t sub_function) {
    return sub_function == static_cast<std::uint16_t>(DiagnosticSub::RestartCommunications) ||
           sub_function == static_cast<std::uint16_t>(DiagnosticSub::ClearCounters);
}

MaybeResponse serve_diagnostics(const protocol::DiagnosticsRequest& request,
                                const DiagnosticsSpec& spec, CommState& state,
                                std::span<std::uint8_t> scratch) {
    const std::uint16_t sub = request.sub_function;
    if (!std::binary_search(spec.sub_functions.begin(), spec.sub_functions.end(), sub)) {
        return exception_response(kFc, ExceptionCode::IllegalFunction);
    }
    const auto which = static_cast<DiagnosticSub>(sub);
    switch (which) {
        case DiagnosticSub::ReturnQueryData:
            return echo(request, spec);
        case DiagnosticSub::RestartCommunications: {
            const bool clear_log = is_word(request.data, 0xFF00);
            if (!clear_log && !is_word(request.data, 0x0000)) break;
            state.pending = clear_log ? PendingReset::RestartClearLog : PendingReset::Restart;
            if (state.listen_only) return std::nullopt;  // [APP]: no answer from listen-only
            return answer(sub, request.data);
        }
        case DiagnosticSub::ChangeAsciiDelimiter:
            if (request.data.size() != 2 || request.data[1] != 0) break;
            state.ascii_delimiter = request.data[0];
            return answer(sub, request.data);
        default:
            break;
    }
    if (which == DiagnosticSub::RestartCommunications ||
        which == DiagnosticSub::ChangeAsciiDelimiter || !is_word(request.data, 0)) {
        return exception_response(kFc, ExceptionCode::IllegalDataValue);
    }
    switch (which) {
        case DiagnosticSub::ReturnDiagnosticRegister:
            return answer_word(sub, state.diagnostic_register, scratch);
        case DiagnosticSub::ForceListenOnly:
            state.listen_only = true;
            state.log.add(event::kEnteredListenOnly);
            return std::nullopt;
        case DiagnosticSub::ClearCounters:
            state.pending = PendingReset::ClearCounters;
            return answer(sub, request.data);
        case DiagnosticSub::ClearOverrunCounter:
            state.counters.overruns = 0;
            return answer(sub, request.data);
        default:
            return answer_word(sub, counter(state.counters, which), scratch);
    }
}

MaybeResponse serve_event_counter(const CommState& state) {
    return protocol::Response{protocol::GetCommEventCounterResponse{0x0000, state.event_count}};
}

MaybeResponse serve_event_log(const CommState& state, std::span<std::uint8_t> scratch) {
    const std::size_t n = state.log.copy(scratch.first(EventLog::kCapacity));
    return protocol::Response{protocol::GetCommEventLogResponse{
        0x0000, state.event_count, state.counters.bus_messages, scratch.first(n)}};
}

}  // namespace mblab::device
