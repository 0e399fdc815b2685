#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

// One well-formed request PDU for each public function code, at address 0 where there is one
// and with the smallest valid quantity: the request a device that serves the function answers
// with data, or with an exception other than 01 (02 when address 0 is not in its map). The tester
// asks it to tell "this function is not served" from "this request was refused".
namespace mblab::conformance {

std::optional<std::vector<std::uint8_t>> plain_request_pdu(std::uint8_t function);

// Every public function code that has one, in ascending order.
std::span<const std::uint8_t> functions_with_plain_requests();

}  // namespace mblab::conformance
