#pragma once

#include <string>
#include <string_view>

// Serial-line frames for test vectors, built from the address and PDU so no vector carries a
// hand-computed checksum.
namespace mblab::test {

// Address + PDU (hex) with its CRC appended, as hex: rtu("01 03 00 00 00 01") is
// "01 03 00 00 00 01 84 0A".
std::string rtu(std::string_view address_and_pdu_hex);
// ':' + hex + LRC + CR LF for address + PDU (hex).
std::string ascii(std::string_view address_and_pdu_hex);

}  // namespace mblab::test
