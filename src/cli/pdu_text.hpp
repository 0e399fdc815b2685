#pragma once

#include <cstdint>
#include <span>
#include <string>

// PDUs as lines of named fields, for --decode and `mblab raw`: "function 0x03 read holding
// registers: starting address 0 (0x0000), quantity 10". Field names follow [APP]'s tables.
namespace mblab::cli {

std::string describe_request_pdu(std::span<const std::uint8_t> pdu);
std::string describe_response_pdu(std::span<const std::uint8_t> pdu);

}  // namespace mblab::cli
