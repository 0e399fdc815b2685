#pragma once

#include <cstdint>
#include <variant>

#include "protocol/function_code.hpp"
#include "protocol/function_table.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

// Function codes of the message types (not part of the public API).
namespace mblab::protocol::detail {

// A type that serves several codes (read bits, read registers, raw) carries its code in a
// `function` member; every other type names its one code as `kFunction`.
template <class Message>
constexpr std::uint8_t function_byte(const Message& message) {
    if constexpr (requires { message.function; }) {
        return static_cast<std::uint8_t>(message.function);
    } else {
        return static_cast<std::uint8_t>(Message::kFunction);
    }
}

template <class Message>
constexpr bool has_row() {
    if constexpr (requires { Message::kFunction; }) {
        return find_function(static_cast<std::uint8_t>(Message::kFunction)) != nullptr;
    } else {
        return true;
    }
}

template <class... Messages>
constexpr bool every_code_has_a_row(const std::variant<Messages...>*) {
    return (has_row<Messages>() && ...);
}

static_assert(every_code_has_a_row(static_cast<const Request*>(nullptr)) &&
                  every_code_has_a_row(static_cast<const Response*>(nullptr)),
              "every code of a message type needs a row");

}  // namespace mblab::protocol::detail
