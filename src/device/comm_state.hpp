#pragma once

#include <cstdint>

#include "device/event_log.hpp"

// A unit's serial-line communication state: the FC 08 counters, the FC 0B event counter and
// the FC 0C log, listen-only mode. On TCP the same state is kept so FC 08/0B/0C answer alike.
namespace mblab::device {

struct CommCounters {                  // 16-bit like the registers FC 08 returns them in; they wrap
    std::uint16_t bus_messages = 0;    // sub 0B
    std::uint16_t bus_errors = 0;      // sub 0C: CRC/LRC, parity, short frames
    std::uint16_t bus_exceptions = 0;  // sub 0D
    std::uint16_t server_messages = 0;  // sub 0E
    std::uint16_t no_response = 0;      // sub 0F
    std::uint16_t naks = 0;             // sub 10
    std::uint16_t busy = 0;             // sub 11
    std::uint16_t overruns = 0;         // sub 12
};

// A restart or counter clear takes effect after its answer is sent ([APP] 6.8.1 sub 01).
enum class PendingReset : std::uint8_t { None, ClearCounters, Restart, RestartClearLog };

struct CommState {
    CommCounters counters;
    EventLog log;
    std::uint16_t event_count = 0;
    std::uint16_t diagnostic_register = 0;
    std::uint8_t ascii_delimiter = '\n';
    bool listen_only = false;
    bool overrun_seen = false;  // since the last receive event
    PendingReset pending = PendingReset::None;

    void apply_pending() {
        if (pending == PendingReset::None) return;
        counters = {};
        event_count = 0;
        if (pending == PendingReset::ClearCounters) {
            diagnostic_register = 0;
        } else {
            if (pending == PendingReset::RestartClearLog) log.clear();
            listen_only = false;
            log.add(event::kRestart);
        }
        pending = PendingReset::None;
    }
};

}  // namespace mblab::device
