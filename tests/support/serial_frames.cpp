#include "support/serial_frames.hpp"

#include <cstdio>

#include "protocol/crc16.hpp"
#include "protocol/lrc.hpp"
#include "support/hex.hpp"

namespace mblab::test {

std::string rtu(std::string_view address_and_pdu_hex) {
    auto bytes = hex(address_and_pdu_hex);
    auto crc = protocol::crc16(bytes);
    bytes.push_back(static_cast<std::uint8_t>(crc & 0xFF));
    bytes.push_back(static_cast<std::uint8_t>(crc >> 8));
    return to_hex(bytes);
}

std::string ascii(std::string_view address_and_pdu_hex) {
    auto bytes = hex(address_and_pdu_hex);
    bytes.push_back(protocol::lrc(bytes));
    std::string out = ":";
    for (auto b : bytes) {
        char digits[3];
        std::snprintf(digits, sizeof digits, "%02X", unsigned{b});
        out += digits;
    }
    return out + "\r\n";
}

}  // namespace mblab::test
