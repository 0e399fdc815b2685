#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <string_view>

#include "client/link.hpp"
#include "client/raw_link.hpp"
#include "protocol/result.hpp"

// What a user names as TARGET: "tcp://HOST[:PORT]" (or "HOST[:PORT]") today; the serial schemes
// rtu://, ascii:// and rtu+tcp:// are recognised so they fail with a clear message until their
// links exist.
namespace mblab::client {

struct Target {
    std::string name;  // normalised: "tcp://127.0.0.1:502"
    Endpoint endpoint;
};

// The error is one line naming the target and the expected form.
protocol::Result<Target, std::string> parse_target(std::string_view text);

// Connects to the target; the error says why it cannot be reached ("connection refused").
protocol::Result<std::unique_ptr<Link>, LinkError> open_link(const Target& target,
                                                            std::chrono::milliseconds timeout);

}  // namespace mblab::client
