#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "client/link.hpp"
#include "client/raw_link.hpp"
#include "protocol/result.hpp"
#include "security/tls_context.hpp"
#include "transport/serial_url.hpp"

// What a user names as TARGET: "tcp://HOST[:PORT]" (or "HOST[:PORT]"), "rtu:///dev/ttyUSB0?baud=
// 19200&parity=E", "ascii:///dev/ttyS0?...", "rtu+tcp://HOST:PORT" (transport/serial_url.hpp),
// "mbaps://HOST[:PORT]" (Modbus/TCP Security, port 802 by default).
namespace mblab::client {

struct Target {
    std::string name;  // normalised: "tcp://127.0.0.1:502", "rtu:///dev/ttyUSB0?baud=19200&..."
    std::optional<Endpoint> tcp;
    std::optional<transport::SerialUrl> serial;
    bool secure = false;      // mbaps://: MBAP inside TLS, once attach_tls() gave it a context
    std::string server_name;  // what the server's certificate must name (mbaps://)
};

// How frames are cut on the target's link: MBAP for tcp://, RTU for rtu:// and rtu+tcp://.
Framing framing_of(const Target& target);

// The error is one line naming the target and the expected form.
protocol::Result<Target, std::string> parse_target(std::string_view text);

// Gives an mbaps:// target its TLS context from --cert/--key/--ca; "" when done, else one line
// (a missing or unreadable file, a key that does not match its certificate). Files given for a
// target that is not mbaps:// are an error too: they would be silently unused.
std::string attach_tls(Target& target, const security::TlsFiles& files,
                       const security::ClientSettings& settings = {});

// Connects to the target; the error says why it cannot be reached ("connection refused").
// `observer` sees the traffic of the link: TCP segments, or a line's frames.
protocol::Result<std::unique_ptr<Link>, LinkError> open_link(const Target& target,
                                                             std::chrono::milliseconds timeout,
                                                             LinkObserver* observer = nullptr);

// Opens a link to a device: open_link on a target, or a test's in-memory link.
using Dial = std::function<protocol::Result<std::unique_ptr<Link>, LinkError>()>;

}  // namespace mblab::client
