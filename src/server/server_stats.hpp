#pragma once

#include <atomic>
#include <cstdint>

// Counters a server keeps while it runs. Written on the server's thread, readable from any.
namespace mblab::server {

struct ServerStats {
    using Counter = std::atomic<std::uint64_t>;

    Counter connections_open{0};
    Counter requests{0};           // whole frames handed to the device
    Counter exceptions{0};         // answers with the exception bit, busy and 9.1.3 included
    Counter busy{0};               // answered 06 for too many outstanding requests
    Counter frames_dropped{0};     // protocol id != 0, unfinished frames
    Counter closed_idle{0};        // idle timer
    Counter closed_bad_frame{0};   // MBAP length the stream cannot recover from
    Counter closed_slow_frame{0};  // a frame still arriving after ServerOptions::frame_limit
    // Modbus/TCP Security (mbaps://)
    Counter tls_handshakes{0};  // completed, resumed ones included
    Counter tls_resumed{0};
    // Handshakes that failed (no, expired, foreign certificate, ...) and clients refused after
    // one (a bare PDU without MBAP).
    Counter tls_refused{0};
    Counter denied{0};  // requests the client's role may not make, answered 01

    static void bump(Counter& counter) { counter.fetch_add(1, std::memory_order_relaxed); }
    static std::uint64_t read(const Counter& counter) {
        return counter.load(std::memory_order_relaxed);
    }
};

}  // namespace mblab::server
