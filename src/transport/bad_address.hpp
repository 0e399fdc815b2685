#pragma once

#include <string>
#include <string_view>

namespace mblab::transport {

// The one-line error of every address parser: "bad address 'URL': WHY (EXPECTED)".
// `expected` names the form, e.g. "expected tcp://HOST:PORT, e.g. tcp://127.0.0.1:502".
std::string bad_address(std::string_view url, std::string_view why, std::string_view expected);

}  // namespace mblab::transport
