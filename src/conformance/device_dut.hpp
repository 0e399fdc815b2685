#pragma once

#include <string>

#include "conformance/dut.hpp"
#include "device/profile.hpp"

namespace mblab::conformance {

// What the built-in reference device declares about its first unit, read from its profile (as
// loaded, before a device takes its data), so `mblab conform` with no target tests it against
// the facts it was built from.
Dut dut_from_profile(const device::Profile& profile, std::string declared_by);

}  // namespace mblab::conformance
