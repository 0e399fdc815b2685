#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "protocol/adu.hpp"
#include "robustness/fuzz_case.hpp"

// The robustness tester on a serial line (rtu://, ascii://, rtu+tcp://): the cases written for
// Modbus/TCP re-framed for the line, and the classes only a line has.
namespace mblab::robustness {

// Address + PDU in RTU or ASCII, whatever the PDU's length (oversize cases go past 256 bytes).
std::vector<std::uint8_t> line_frame(protocol::Framing framing, std::uint8_t address,
                                     std::span<const std::uint8_t> pdu);

// Why a class is not tried over `framing` (an MBAP field on a line, a line fault over
// Modbus/TCP), or nothing when it is.
std::optional<std::string_view> not_applicable(BadInput kind, protocol::Framing framing);

// A Modbus/TCP case re-framed for the line: each step's unit id and PDU as an address and PDU
// with its CRC or LRC. Nothing when the case tests what a line does not carry (the class is not
// applicable, or a step is not one whole MBAP frame with protocol id 0 and a true length).
std::optional<FuzzCase> on_line(const FuzzCase& c, protocol::Framing framing);

// The line-only classes' cases for a device at `address` that answers a read of `reg`: bad CRC or
// LRC, short frames, an RTU frame cut by `gap` (longer than t1.5), noise before a good frame,
// broken ASCII text. Each ends with the good read where the class is about recovering.
std::vector<FuzzCase> line_cases(protocol::Framing framing, std::uint8_t address, std::uint16_t reg,
                                 std::chrono::milliseconds gap);

}  // namespace mblab::robustness
