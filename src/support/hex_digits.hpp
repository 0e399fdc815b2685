#pragma once

// Hex digits, both ways, for every text form here that spells bytes in hex: ASCII frames (upper
// case only [SER 2.5.2.1]), journal and state files, request templates, HTTP percent-escapes.
namespace mblab {

inline constexpr char kHexDigits[] = "0123456789ABCDEF";

// The value of an upper-case hex digit; -1 for anything else, lower case included.
constexpr int upper_hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// The value of a hex digit of either case; -1 for anything else.
constexpr int hex_value(char c) {
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return upper_hex_value(c);
}

}  // namespace mblab
