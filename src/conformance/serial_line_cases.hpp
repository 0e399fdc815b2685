#pragma once

// The serial suite's procedures (catalogue/serial.toml): the rules of a multi-drop line that a
// request/answer case in the catalogue's MBAP notation cannot state. Each runs on RTU, ASCII or
// RTU over TCP only (`requires = ["line"]`).
namespace mblab::conformance {

class Session;
struct Case;
struct Outcome;

// FC 03 to another address is not answered [SER 2.2].
Outcome run_other_address_read(Session& session, const Case& c);
// FC 06 to another address is neither answered nor executed [SER 2.2].
Outcome run_other_address_write(Session& session, const Case& c);
// FC 06 to address 0 is executed, not answered, and the device answers again once the declared
// turnaround delay is over [SER 2.2, 2.4.1].
Outcome run_broadcast_write(Session& session, const Case& c);
// A read (`function` 3) or FC 08 (`function` 8) to address 0 is never answered [SER 2.2].
Outcome run_broadcast_unanswered(Session& session, const Case& c);
// A write with a wrong CRC or LRC is neither answered nor executed, and FC 08 sub-function 0C
// counts it where it is served [SER 2.4.2, 2.5.1.2, 2.5.2.2, 6.1].
Outcome run_wrong_checksum(Session& session, const Case& c);
// The answer carries the device's own address, its checksum laid out as the framing says, and
// nothing after it [SER 2.5.1, 2.5.2].
Outcome run_answer_frame(Session& session, const Case& c);
// ASCII: a write in lower-case hex is a framing error, neither answered nor executed [SER 2.5.2].
Outcome run_ascii_lower_case(Session& session, const Case& c);

// The timing cases (line_timing_cases.cpp), on a serial port only (`requires =
// ["serial_port"]`): over RTU over TCP frames are cut by their length.
// RTU: FC 06 broken by a silence over t1.5 is neither answered nor executed [SER 2.5.1.1].
// ASCII: FC 03 with a pause under 1 s between its characters is answered [SER 2.5.2.1].
Outcome run_broken_request(Session& session, const Case& c);
// FC 03 reads, each sent t3.5 after the last answer, are all answered, with no silence over t1.5
// inside an answer; the response times are reported against the timeout [SER 2.5.1.1, 2.4.1].
Outcome run_answer_timing(Session& session, const Case& c);

}  // namespace mblab::conformance
