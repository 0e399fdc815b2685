#pragma once

#include <cstdint>
#include <span>

#include "device/comm_state.hpp"
#include "device/maybe_response.hpp"
#include "device/profile.hpp"
#include "protocol/request.hpp"

// FC 08 (every sub-function of [APP] 6.8), FC 0B and FC 0C over a unit's CommState.
// `scratch` holds response bytes the outcome points into.
namespace mblab::device {

MaybeResponse serve_diagnostics(const protocol::DiagnosticsRequest& request,
                                const DiagnosticsSpec& spec, CommState& state,
                                std::span<std::uint8_t> scratch);
MaybeResponse serve_event_counter(const CommState& state);
MaybeResponse serve_event_log(const CommState& state, std::span<std::uint8_t> scratch);

// FC 08 sub-functions that reset the event counter, so their own answer does not count.
bool resets_event_counter(std::uint16_t sub_function);

}  // namespace mblab::device
