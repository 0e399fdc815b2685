#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "client/link.hpp"

// After a request went unanswered, the client and the tester both ask which unit id the device
// does answer, so the message can say which `--unit` to use.
namespace mblab::client {

// What is asked: a one-register FC 03 read, never the unanswered request itself. A write must
// never reach another unit (on a gateway that is another device, and 0 is a broadcast); any
// answer, an exception included, shows the unit is there.
inline constexpr std::array<std::uint8_t, 5> kUnitProbePdu = {0x03, 0x00, 0x00, 0x00, 0x01};

// Asks `asked` first (when it answers, the unit id is not what went wrong and nothing is said),
// then 1, 255 and 0 over TCP (1 only on a serial line, where 0 is the broadcast). `answers(unit)`
// sends kUnitProbePdu to that unit, on a fresh connection, and tells whether an answer came.
// Returns "; the device answers unit 255: try --unit 255", "; units 255 and 0 did not answer
// either", or nothing.
std::string probe_units(Framing framing, std::uint8_t asked,
                        const std::function<bool(std::uint8_t unit)>& answers);

}  // namespace mblab::client
