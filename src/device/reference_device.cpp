#include "device/reference_device.hpp"

#include <algorithm>

#include "device/diagnostics.hpp"
#include "device/request_scope.hpp"
#include "protocol/function_table.hpp"
#include "protocol/response.hpp"

namespace mblab::device {

namespace {

using protocol::ExceptionCode;
using protocol::FunctionCode;

constexpr std::uint8_t kTcpDirectUnit = 0xFF;

constexpr std::uint8_t code(FunctionCode fc) {
    return static_cast<std::uint8_t>(fc);
}

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
    : profile_(std::move(profile)), prng_(profile_.fault_seed) {
    unit_index_.fill(-1);
    units_.reserve(profile_.units.size());
    for (const auto& spec : profile_.units) {
        unit_index_[spec.id] = static_cast<std::int16_t>(units_.size());
        units_.emplace_back(spec);
        // Units draw apart: the same behaviours on two units do not move in step.
        behaviours_.emplace_back(spec.behaviours,
                                 profile_.behaviour_seed ^ (spec.id * 0x100000001ULL));
    }
    // The units hold the data now.
    for (auto& spec : profile_.units)
        spec = units_[static_cast<std::size_t>(unit_index_[spec.id])].spec();
}

UnitModel* ReferenceDevice::find_unit(std::uint8_t id) {
    const auto i = unit_index_[id];
    return i < 0 ? nullptr : &units_[static_cast<std::size_t>(i)];
}

const UnitModel* ReferenceDevice::find_unit(std::uint8_t id) const {
    const auto i = unit_index_[id];
    return i < 0 ? nullptr : &units_[static_cast<std::size_t>(i)];
}

ReferenceDevice::Route ReferenceDevice::route(const RequestContext& context) {
    if (UnitModel* unit = find_unit(context.unit)) return {RouteKind::Unit, unit};
    if (context.link == Link::Serial) {
        return {context.unit == 0 ? RouteKind::Broadcast : RouteKind::Silent, nullptr};
    }
    if (context.unit == 0 || context.unit == kTcpDirectUnit)
        return {RouteKind::Unit, &units_.front()};
    switch (profile_.unmatched_unit) {
        case UnmatchedUnit::FirstUnit:
            return {RouteKind::Unit, &units_.front()};
        case UnmatchedUnit::Ignore:
            return {RouteKind::Silent, nullptr};
        case UnmatchedUnit::PathUnavailable:
            return {RouteKind::Gateway, nullptr, ExceptionCode::GatewayPathUnavailable};
        case UnmatchedUnit::TargetFailed:
            return {RouteKind::Gateway, nullptr, ExceptionCode::GatewayTargetFailedToRespond};
    }
    return {};
}

Reply ReferenceDevice::handle(const RequestContext& context, std::span<const std::uint8_t> request,
                              std::span<std::uint8_t> response) {
    std::lock_guard lock(mutex_);
    for (auto& unit : units_)
        ++unit.comm().counters.bus_messages;
    if (request.empty()) return silent();
    const Route target = route(context);
    switch (target.kind) {
        case RouteKind::Unit:
            return serve(*target.unit, request, response, false);
        case RouteKind::Broadcast:
            for (auto& unit : units_)
                serve(unit, request, response, true);
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
}

std::uint64_t ReferenceDevice::state_writes() const {
    std::lock_guard lock(mutex_);
    return state_writes_;
}

bool ReferenceDevice::replay_write(const RequestContext& context,
                                   std::span<const std::uint8_t> request) {
    std::lock_guard lock(mutex_);
    if (request.empty() || row_of(request[0]).writes != protocol::Writes::Yes) return false;
    const auto decoded = protocol::decode_request(request);
    const Route target = route(context);
    if (!decoded) return false;
    auto run = [&](UnitModel& unit) {
        const auto outcome = unit.serve(decoded.value(), scratch_);
        return outcome && !std::holds_alternative<protocol::ExceptionResponse>(*outcome);
    };
    if (target.kind == RouteKind::Unit) return run(*target.unit);
    if (target.kind != RouteKind::Broadcast) return false;
    for (auto& unit : units_)
        run(unit);
    return true;
}

Reply ReferenceDevice::serve(UnitModel& unit, std::span<const std::uint8_t> request,
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
            ++state_writes_;
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

void ReferenceDevice::count_bus_error() {
    for (auto& unit : units_)
        ++unit.comm().counters.bus_errors;
}

void ReferenceDevice::count_crc_error() {
    std::lock_guard lock(mutex_);
    count_bus_error();
}

void ReferenceDevice::count_parity_error() {
    std::lock_guard lock(mutex_);
    count_bus_error();
}

void ReferenceDevice::count_short_frame() {
    std::lock_guard lock(mutex_);
    count_bus_error();
}

void ReferenceDevice::count_overrun() {
    std::lock_guard lock(mutex_);
    for (auto& unit : units_) {
        ++unit.comm().counters.overruns;
        unit.comm().overrun_seen = true;
    }
}

void ReferenceDevice::count_busy_reply(std::uint8_t id) {
    std::lock_guard lock(mutex_);
    if (UnitModel* unit = find_unit(id)) {
        ++unit->comm().counters.busy;
        ++unit->comm().counters.bus_exceptions;
    }
}

std::string ReferenceDevice::addressing(Link link) const {
    const auto ids = unit_ids();
    std::string list;
    for (std::size_t i = 0; i < ids.size(); ++i)
        list += (i ? "," : "") + std::to_string(ids[i]);
    if (link == Link::Serial) {
        return (ids.size() == 1 ? "address " : "addresses ") + list +
               " (0 is a broadcast; other addresses are not answered)";
    }
    const std::string units = (ids.size() == 1 ? "unit " : "units ") + list;
    const std::string first = std::to_string(ids.front());
    std::string others = "other unit ids are not answered";
    switch (profile_.unmatched_unit) {
        case UnmatchedUnit::FirstUnit:
            return units + " (0, 255 and every other unit id answer as " + first + ")";
        case UnmatchedUnit::Ignore:
            break;
        case UnmatchedUnit::PathUnavailable:
            others = "other unit ids are answered exception 0A, as by a gateway";
            break;
        case UnmatchedUnit::TargetFailed:
            others = "other unit ids are answered exception 0B, as by a gateway";
            break;
    }
    return units + " (0 and 255 answer as " + first + "; " + others + ")";
}

std::vector<std::uint8_t> ReferenceDevice::unit_ids() const {
    std::vector<std::uint8_t> ids;
    for (const auto& unit : units_)
        ids.push_back(unit.spec().id);
    return ids;
}

std::optional<UnitDeclaration> ReferenceDevice::declaration(std::uint8_t id) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    const UnitSpec& spec = unit->spec();
    UnitDeclaration out;
    out.unit = spec.id;
    out.max_read_registers = spec.max_read_registers;
    out.max_read_bits = spec.max_read_bits;
    out.holding_registers = unit->bank(BankKind::HoldingRegisters).contiguous_from_zero();
    out.semi_signature = spec.semi_signature;
    out.object_messaging = spec.functions[code(FunctionCode::ObjectMessaging)];
    out.functions = spec.functions;
    return out;
}

UnitDeclaration ReferenceDevice::declaration() const {
    return *declaration(units_.front().spec().id);
}

std::optional<UnitStats> ReferenceDevice::stats(std::uint8_t id) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    return UnitStats{id, unit->comm().counters, unit->comm().event_count, unit->comm().listen_only};
}

std::uint8_t ReferenceDevice::ascii_delimiter(std::uint8_t id) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    return unit ? unit->comm().ascii_delimiter : static_cast<std::uint8_t>('\n');
}

std::optional<std::uint16_t> ReferenceDevice::value(std::uint8_t id, BankKind kind,
                                                    std::uint16_t address) const {
    std::lock_guard lock(mutex_);
    const UnitModel* unit = find_unit(id);
    if (!unit) return std::nullopt;
    const auto span = unit->bank(kind).find(address, 1);
    if (!span.mapped) return std::nullopt;
    return unit->bank(kind).at(span.index);
}

void ReferenceDevice::advance(std::chrono::steady_clock::time_point now,
                              std::chrono::system_clock::time_point wall) {
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < units_.size(); ++i)
        behaviours_[i].advance(now, wall, units_[i]);
}

std::chrono::steady_clock::time_point ReferenceDevice::behaviour_deadline() const {
    std::lock_guard lock(mutex_);
    auto next = std::chrono::steady_clock::time_point::max();
    for (const auto& engine : behaviours_)
        next = std::min(next, engine.deadline());
    return next;
}

bool ReferenceDevice::set_value(std::uint8_t id, BankKind kind, std::uint16_t address,
                                std::uint16_t value) {
    std::lock_guard lock(mutex_);
    UnitModel* unit = find_unit(id);
    if (!unit) return false;
    const auto span = unit->bank(kind).find(address, 1);
    if (!span.mapped) return false;
    unit->bank(kind).at(span.index) = value;
    return true;
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
