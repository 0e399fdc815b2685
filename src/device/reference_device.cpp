#include "device/reference_device.hpp"

#include <algorithm>

#include "device/diagnostics.hpp"
#include "device/request_scope.hpp"
#include "protocol/function_table.hpp"
#include "protocol/response.hpp"

namespace mblab::device {

namespace {

using protocol::ExceptionCode;

// Codes without a row: not run on broadcast, no state change, an event, no addresses.
constexpr protocol::FunctionRow kUnlisted{};

const protocol::FunctionRow& row_of(std::uint8_t function) {
    const protocol::FunctionRow* row = protocol::find_function(function);
    return row ? *row : kUnlisted;
}

// FC 08 is an event unless its sub-function resets the counter it would add to.
bool counts_as_event(const protocol::FunctionRow& row,
                     const protocol::Result<protocol::Request>& decoded) {
    switch (row.events) {
        case protocol::EventCounting::Counts:
            return true;
        case protocol::EventCounting::Never:
            return false;
        case protocol::EventCounting::BySubFunction: {
            const auto* diag =
                decoded ? std::get_if<protocol::DiagnosticsRequest>(&decoded.value()) : nullptr;
            return !diag || !resets_event_counter(diag->sub_function);
        }
    }
    return true;
}

bool is_restart(const protocol::Result<protocol::Request>& decoded) {
    if (!decoded) return false;
    const auto* diag = std::get_if<protocol::DiagnosticsRequest>(&decoded.value());
    return diag && diag->sub_function ==
                       static_cast<std::uint16_t>(protocol::DiagnosticSub::RestartCommunications);
}

std::uint8_t send_event(ExceptionCode code) {
    switch (code) {
        case ExceptionCode::IllegalFunction:
        case ExceptionCode::IllegalDataAddress:
        case ExceptionCode::IllegalDataValue:
            return event::kSendReadException;
        case ExceptionCode::ServerDeviceFailure:
            return event::kSendAbortException;
        case ExceptionCode::Acknowledge:
        case ExceptionCode::ServerDeviceBusy:
            return event::kSendBusyException;
        case ExceptionCode::NegativeAcknowledge:
            return event::kSendNakException;
        default:
            return 0;
    }
}

Reply silent() {
    return Reply{ReplyAction::NoAnswer, 0, {}};
}

}  // namespace

ReferenceDevice::ReferenceDevice(Profile profile)
    : units_(std::move(profile)), prng_(units_.profile().fault_seed) {}

Reply ReferenceDevice::handle(const RequestContext& context, std::span<const std::uint8_t> request,
                              std::span<std::uint8_t> response) {
    return units_.locked([&](UnitTable& table) {
        for (auto& unit : table.units)
            ++unit.comm().counters.bus_messages;
        if (request.empty()) return silent();
        const Route target = table.route(context);
        switch (target.kind) {
            case RouteKind::Unit:
                return serve(table, *target.unit, request, response, false);
            case RouteKind::Broadcast:
                for (auto& unit : table.units)
                    serve(table, unit, request, response, true);
                return silent();
            case RouteKind::Gateway: {
                protocol::WriteCursor out(response);
                protocol::encode_exception(request[0], target.gateway, out);
                return Reply{ReplyAction::Answer, out.size(), {}};
            }
            case RouteKind::Silent:
                break;
        }
        return silent();
    });
}

Reply ReferenceDevice::serve(UnitTable& table, UnitModel& unit,
                             std::span<const std::uint8_t> request,
                             std::span<std::uint8_t> response, bool broadcast) {
    CommState& comm = unit.comm();
    ++comm.counters.server_messages;
    std::uint8_t received = event::kReceive;
    if (comm.overrun_seen) received |= event::kReceiveOverrun;
    if (comm.listen_only) received |= event::kReceiveListenOnly;
    if (broadcast) received |= event::kReceiveBroadcast;
    comm.overrun_seen = false;
    comm.log.add(received);

    const std::uint8_t function = request[0];
    const protocol::FunctionRow& row = row_of(function);
    const auto decoded = protocol::decode_request(request);
    if (comm.listen_only) {
        ++comm.counters.no_response;
        if (!broadcast && is_restart(decoded)) {
            unit.serve(decoded.value(), scratch_);
            comm.apply_pending();
        }
        return silent();
    }

    std::chrono::milliseconds delay{0};
    MaybeResponse outcome;
    const FaultSpec* fault =
        broadcast ? nullptr : unit.faults().fire(scope_of(function, decoded), prng_);
    if (fault) {
        switch (fault->action) {
            case FaultAction::Delay:
                delay = fault->delay;
                break;
            case FaultAction::Drop:
                ++comm.counters.no_response;
                return silent();
            case FaultAction::Close:
                ++comm.counters.no_response;
                return Reply{ReplyAction::Close, 0, {}};
            case FaultAction::Exception:
                outcome = exception_response(function, fault->exception);
                break;
            case FaultAction::Garbage:
                return garbage(fault->garbage_bytes, response);
        }
    }
    if (outcome) {
        // the fault answers in the request's place
    } else if (!unit.supports(function)) {
        outcome = exception_response(function, ExceptionCode::IllegalFunction);
    } else if (!decoded) {
        outcome = exception_response(function, decoded.error().exception);
    } else if (!broadcast || row.broadcast == protocol::Broadcast::Execute) {
        outcome = unit.serve(decoded.value(), scratch_);
        if (row.writes == protocol::Writes::Yes && outcome &&
            !std::holds_alternative<protocol::ExceptionResponse>(*outcome)) {
            ++table.state_writes;
        }
    }

    const bool is_event = counts_as_event(row, decoded);
    if (broadcast || !outcome) {
        const bool completed =
            outcome && !std::holds_alternative<protocol::ExceptionResponse>(*outcome);
        if (completed && is_event) ++comm.event_count;
        ++comm.counters.no_response;
        comm.apply_pending();
        return silent();
    }
    Reply reply = answer(unit, function, outcome, response, is_event);
    reply.delay = delay;
    comm.apply_pending();
    return reply;
}

Reply ReferenceDevice::answer(UnitModel& unit, std::uint8_t function, const MaybeResponse& outcome,
                              std::span<std::uint8_t> response, bool counts_as_event) {
    CommState& comm = unit.comm();
    protocol::WriteCursor out(response);
    std::uint8_t sent = event::kSend;
    if (comm.listen_only) sent |= event::kSendListenOnly;
    const auto* refusal = std::get_if<protocol::ExceptionResponse>(&*outcome);
    bool written = refusal ? protocol::encode_exception(function, refusal->code, out)
                           : protocol::encode_response(*outcome, out);
    ExceptionCode code = refusal ? refusal->code : ExceptionCode::ServerDeviceFailure;
    if (!written) {
        // A response the codec refuses is the device's failure, not the client's.
        out = protocol::WriteCursor(response);
        protocol::encode_exception(function, ExceptionCode::ServerDeviceFailure, out);
    }
    if (refusal || !written) {
        ++comm.counters.bus_exceptions;
        if (code == ExceptionCode::NegativeAcknowledge) ++comm.counters.naks;
        if (code == ExceptionCode::ServerDeviceBusy) ++comm.counters.busy;
        sent |= send_event(code);
    } else if (counts_as_event) {
        ++comm.event_count;
    }
    comm.log.add(sent);
    return Reply{ReplyAction::Answer, out.size(), {}};
}

Reply ReferenceDevice::garbage(std::size_t size, std::span<std::uint8_t> response) {
    size = std::min(size, response.size());
    for (std::size_t i = 0; i < size; ++i)
        response[i] = static_cast<std::uint8_t>(prng_.next());
    return Reply{ReplyAction::Answer, size, {}};
}

Loaded<std::unique_ptr<ReferenceDevice>> load_profile(const std::filesystem::path& path) {
    auto profile = read_profile(path);
    if (!profile) return profile.error();
    return std::make_unique<ReferenceDevice>(std::move(profile).value());
}

Loaded<std::unique_ptr<ReferenceDevice>> load_profile_text(std::string_view text,
                                                           std::string_view name) {
    auto profile = parse_profile(text, name);
    if (!profile) return profile.error();
    return std::make_unique<ReferenceDevice>(std::move(profile).value());
}

}  // namespace mblab::device
