#pragma once

#include <cstdint>
#include <optional>

#include "protocol/response.hpp"

namespace mblab::device {

// What serving one request gives: the response (an exception response included), or no
// answer at all (listen-only mode, entering it, a restart from it).
using MaybeResponse = std::optional<protocol::Response>;

inline MaybeResponse exception_response(std::uint8_t function, protocol::ExceptionCode code) {
    return protocol::Response{protocol::ExceptionResponse{function, code}};
}

}  // namespace mblab::device
