#pragma once

#include <cstdint>

#include "protocol/request.hpp"
#include "protocol/result.hpp"

namespace mblab::device {

// The data addresses a request names, for rules that filter by address (fault rules, role rules).
struct RequestScope {
    std::uint8_t function = 0;
    bool has_addresses = false;  // false when the request names no data address (or is bad)
    std::uint32_t first = 0;
    std::uint32_t last = 0;  // inclusive
};

// From the function code's row (protocol/function_table.hpp) and the decoded request.
RequestScope scope_of(std::uint8_t function, const protocol::Result<protocol::Request>& decoded);

}  // namespace mblab::device
