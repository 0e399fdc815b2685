#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "device/comm_state.hpp"
#include "device/device_units.hpp"

// The units' line and diagnostic counters outside a request: the events a serial server sees
// before a frame reaches the device, and the FC 08 / 0B / 0C state read and cleared by the HTTP
// API and the tests. Each call takes the device's lock once (device_units.hpp).
namespace mblab::device {

struct UnitStats {
    std::uint8_t unit = 0;
    CommCounters counters;
    std::uint16_t event_count = 0;
    bool listen_only = false;
};

class LineCounters {
  public:
    explicit LineCounters(DeviceUnits& units) : units_(units) {}

    // Line events; every unit on the line counts them (FC 08 sub 0C and 12).
    void count_crc_error();  // CRC-16 or LRC mismatch
    void count_parity_error();
    void count_short_frame();  // fewer than 3 bytes, or cut by a t1.5 gap
    void count_overrun();
    // The server answered exception 06 itself (too many requests in flight) for `unit`.
    void count_busy_reply(std::uint8_t unit);

    // nullopt / false when the profile has no such unit.
    std::optional<UnitStats> stats(std::uint8_t unit) const;
    // The FC 08 counters and event counter, as sub-function 0A clears them; the log stays.
    bool clear_counters(std::uint8_t unit);
    // The FC 0C event log, newest first.
    std::optional<std::vector<std::uint8_t>> event_log(std::uint8_t unit) const;
    // The FC 08 sub 03 delimiter the ASCII framer should expect (default LF).
    std::uint8_t ascii_delimiter(std::uint8_t unit) const;

  private:
    void count_bus_error();

    DeviceUnits& units_;
};

}  // namespace mblab::device
