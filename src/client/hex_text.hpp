#pragma once

#include <string>

// How every client message shows a field's value, so that a transaction id, a function code or
// an address reads the same in all of them.
namespace mblab::client {

// "0x002A"
std::string hex16(unsigned value);
// "0x2A"
std::string hex8(unsigned value);

}  // namespace mblab::client
