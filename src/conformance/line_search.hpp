#pragma once

#include <chrono>
#include <string>

#include "client/target.hpp"
#include "conformance/dut.hpp"

// A device on a serial line that answers nothing may simply be set to another baud rate,
// parity or stop bits than the target's URL says [SER 2.5.1, 2.5.2]. The settings the DUT file
// declares (`line_settings`) are tried in turn, so that the one-line error can say which one
// the device answers at.
namespace mblab::conformance {

// "" when nothing is declared, the target is not a serial port, or no declared setting gets an
// answer to an FC 03 read at the DUT's unit; otherwise "; it answers at baud=9600&parity=N&stop=2
// (declared in line_settings): run with rtu:///dev/ttyUSB0?baud=9600&parity=N&stop=2&data=8".
std::string line_search_hint(const client::Target& target, const Dut& dut,
                             std::chrono::milliseconds timeout);

}  // namespace mblab::conformance
