#pragma once

#include <cstdint>

namespace mblab::protocol {

// Which way a PDU travels: requests and responses of one function code have different layouts.
enum class Direction : std::uint8_t { Request, Response };

}  // namespace mblab::protocol
