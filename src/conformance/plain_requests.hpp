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

// For a function that writes, a request a device serving it must refuse with exception 03 (a
// quantity of 0, a byte count of 0, a coil value other than 0000/FF00, a PDU cut short), so asking
// changes nothing and 01 still says "not served"; for any other function (FC 16's mask write of
// AND FFFF, OR 0000 included, which keeps the value), its plain request.
std::optional<std::vector<std::uint8_t>> harmless_request_pdu(std::uint8_t function);

// A write of coil 0 or register 0 that leaves it as it is: for FC 05, 06, 0F, 10 and 17, the read
// whose answer says what is there now (FC 01 of coil 0, FC 03 of register 0), and the write of
// that answer's value back; nullopt for other functions or an answer that is not the read's data.
std::optional<std::vector<std::uint8_t>> read_before_write_back(std::uint8_t function);
std::optional<std::vector<std::uint8_t>> write_back_pdu(std::uint8_t function,
                                                        std::span<const std::uint8_t> read_answer);

}  // namespace mblab::conformance
