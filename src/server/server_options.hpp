#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "transport/allow_list.hpp"

namespace mblab::server {

struct ServerOptions {
    // Connections admitted at once; when full, the oldest idle one is closed to admit a new
    // one ([TCPG] 4.2.1.1). 0: no limit.
    std::size_t max_connections = 256;
    // A connection without a whole request or an answer for this long is closed; this also
    // ends slowloris clients that send part of a header and go quiet. 0: never.
    std::chrono::milliseconds idle_timeout{60'000};
    // How long an unfinished frame may wait for its missing bytes before it is answered with
    // exception 03 (seed 000 9.1.3) and dropped, so the stream stays in step.
    std::chrono::milliseconds partial_frame_timeout{250};
    // Requests a connection may have waiting for their answers; past it a request is answered
    // with exception 06 (server device busy).
    std::size_t max_outstanding = 16;
    transport::AllowList allow;  // empty: every client
    // Told the unit of each busy answer the server gives itself, so a device can count it
    // (FC 08 sub 11). Called on the server's thread.
    std::function<void(std::uint8_t unit)> on_busy_reply;
};

}  // namespace mblab::server
