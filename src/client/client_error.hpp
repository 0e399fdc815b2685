#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "protocol/exception_code.hpp"

namespace mblab::client {

enum class ErrorKind : std::uint8_t {
    Invalid,    // the client refused to send the request (a quantity over [APP]'s limit, ...)
    Connect,    // the target cannot be reached
    Timeout,    // no answer before the deadline, on every try
    Closed,     // the device closed the connection instead of answering
    BadAnswer,  // an answer that is not a valid answer to the request (wrong id, code, length)
    Exception,  // the device answered with an exception
};

// One line for the user, without the command prefix, e.g. "exception 02 illegal data address:
// 0x04A1 is not on this device".
struct ClientError {
    ErrorKind kind = ErrorKind::BadAnswer;
    std::string message;
    std::optional<protocol::ExceptionCode> exception;  // kind == Exception
};

// "invalid", "connect", "timeout", "closed", "bad-answer", "exception" (for JSON output).
const char* error_kind_name(ErrorKind kind);

}  // namespace mblab::client
