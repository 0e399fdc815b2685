#pragma once

#include "device/behaviour_spec.hpp"
#include "device/toml_fields.hpp"

// The parts of a behaviour table every behaviour shares, whether it names its registers by
// address ([[unit.behaviours]]) or a SunSpec point by name ([[unit.sunspec.model.behaviours]]).
namespace mblab::device {

// kind and interval_ms.
bool load_behaviour_kind(Fields& fields, BehaviourSpec& out);
// The fields out.kind takes (value; min, max and period_ms; step and start; source and lag_ms);
// out.layout must be set first, as a counter's default max is the largest value it holds.
bool load_behaviour_motion(Fields& fields, BehaviourSpec& out);

}  // namespace mblab::device
