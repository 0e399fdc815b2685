#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "support/hex_digits.hpp"

// Bytes from a peer shown as text: printable ASCII as it is (a backslash doubled), any other byte
// as \xNN. What a device or a client sends then cannot put bytes that are not text (which a JSON
// or XML report cannot carry), or terminal escapes, into a console line or a report.
namespace mblab {

inline void append_escaped(std::string& out, std::uint8_t byte) {
    if (byte == '\\') {
        out += "\\\\";  // so that \xNN always means an escaped byte
    } else if (byte >= 0x20 && byte < 0x7F) {
        out += static_cast<char>(byte);
    } else {
        out += {'\\', 'x', kHexDigits[byte >> 4], kHexDigits[byte & 0x0F]};
    }
}

inline std::string escaped_text(std::span<const std::uint8_t> bytes) {
    std::string out;
    out.reserve(bytes.size());
    for (const auto byte : bytes)
        append_escaped(out, byte);
    return out;
}

}  // namespace mblab
