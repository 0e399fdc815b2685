#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "device/behaviour_spec.hpp"
#include "device/sunspec_chain.hpp"
#include "device/toml_fields.hpp"

// [[unit.sunspec.model.behaviours]]: a value that moves on a SunSpec point named, in engineering
// units (docs/sunspec.md "Values that move"). The register holds value / 10^sf, the scale factor
// read from its register when each update is computed (SunSpec Information Model
// Specification, "Scale factors"); a multi-register point is written whole under the device's
// lock, so no read sees half of an update; an accumulator only increases.
namespace mblab::device {

// Loads the behaviours of one model table (`model`, its [[unit.sunspec.model]] of id `id`)
// against the points the chain laid for it, appending them to `out`. Each driven point's range
// in `ranges` starts at the behaviour's first value, so it is valid before the first update (a
// device whose behaviours never run, as conform's built-in one, keeps it). An error is one line
// naming the model and the point.
bool load_sunspec_behaviours(Fields& model, std::uint16_t id,
                             const std::map<std::string, SunSpecPlacedPoint>& points,
                             std::vector<RangeSpec>& ranges, std::vector<BehaviourSpec>& out);

}  // namespace mblab::device
