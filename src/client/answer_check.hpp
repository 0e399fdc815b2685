#pragma once

#include <optional>
#include <string>

#include "protocol/exception_code.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

// What the codec cannot know alone: whether a well-formed answer answers this request.
namespace mblab::client {

// Why `response` is not the answer to `request` (a count, an echo or a sub-function that differs),
// or nothing when it is. Exception answers are not judged here.
std::optional<std::string> answer_mismatch(const protocol::Request& request,
                                           const protocol::Response& response);

// "exception 02 illegal data address: 0x04A1 is not on this device": the code, its name, and
// what it means for this request.
std::string describe_exception(const protocol::Request& request, protocol::ExceptionCode code);

}  // namespace mblab::client
