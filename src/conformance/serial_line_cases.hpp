#pragma once

#include <vector>

#include "conformance/procedures.hpp"

// The serial suite's procedures (catalogue/serial.toml): the rules of a multi-drop line that a
// request/answer case in the catalogue's MBAP notation cannot state. Each runs on RTU, ASCII or
// RTU over TCP only (`requires = ["line"]`).
namespace mblab::conformance {

std::vector<ProcedureInfo> serial_line_procedures();
// The timing cases (line_timing_cases.cpp), on a serial port only (`requires =
// ["serial_port"]`): over RTU over TCP frames are cut by their length.
std::vector<ProcedureInfo> line_timing_procedures();

}  // namespace mblab::conformance
