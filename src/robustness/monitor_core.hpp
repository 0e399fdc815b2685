#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "robustness/run_clock.hpp"

// The essential-function monitor without I/O: the job the device is there to do, watched on a
// connection of its own beside the robustness run. By default a write/read-back loop on one
// holding register (an I/O gateway's loop): every period, FC 06 writes a value that changes each
// cycle, then FC 03 reads it back; the cycle holds when the value read is the one written within
// the budget. Bytes and time in, bytes to send out: the owner sends what poll() returns, gives
// received() what the connection reads, and wakes the core at deadline(). Tests drive it with a
// manual clock, hex in and hex out.
namespace mblab::robustness {

struct MonitorSpec {
    std::uint8_t unit = 1;
    std::uint16_t address = 0;  // the holding register written and read back
    std::chrono::milliseconds period{100};
    std::chrono::milliseconds budget{50};  // at most the period
    double miss_percent = 0;  // missed cycles tolerated in a phase, in percent of its cycles
    bool read_only = false;   // the read alone, its latency judged (a device with no register
                              // the monitor may write)
};

struct MonitorCycle {
    Clock::time_point started{};
    // When it held: the device's time, from each request's send to its answer (the tester's own
    // time between the write's echo and the read-back's send is not the device's).
    std::optional<std::chrono::microseconds> latency;
    std::string missed;  // why it did not: "no answer within 50 ms", "read 7 after writing 8"
    bool held() const { return latency.has_value(); }
    // Neither held nor missed yet: the cycle under way when the monitor stopped.
    bool pending() const { return !held() && missed.empty(); }
};

class MonitorCore {
  public:
    MonitorCore(MonitorSpec spec, Clock::time_point now);

    // Moves time on: a cycle whose budget has passed is missed, and a new one starts on its
    // period. The bytes to send now (a request), or none.
    std::vector<std::uint8_t> poll(Clock::time_point now);
    // Bytes the connection read, arrived at `now` (the kernel's arrival time where the owner knows
    // it: a tester starved of CPU must not blame the device for answers it read late).
    void received(std::span<const std::uint8_t> bytes, Clock::time_point now);
    // The connection closed or broke: the cycle under way is missed; the owner opens another.
    void connection_lost(Clock::time_point now);
    // When poll() must be called next.
    Clock::time_point deadline() const;

    const std::vector<MonitorCycle>& cycles() const { return cycles_; }
    const MonitorSpec& spec() const { return spec_; }

  private:
    enum class Waiting : std::uint8_t { Nothing, Write, Read };
    std::vector<std::uint8_t> request(std::span<const std::uint8_t> pdu);
    void answer(std::span<const std::uint8_t> pdu, Clock::time_point now);
    void miss(std::string why);

    MonitorSpec spec_;
    Clock::time_point next_start_;
    Waiting waiting_ = Waiting::Nothing;
    bool pending_read_ = false;  // the write was echoed: the read-back is poll()'s to send
    std::uint16_t transaction_ = 0;
    std::uint16_t value_ = 0;              // written this cycle
    Clock::time_point sent_{};             // the request under way went out
    std::chrono::microseconds device_{0};  // the device's time so far this cycle
    std::vector<std::uint8_t> input_;
    std::vector<MonitorCycle> cycles_;
};

}  // namespace mblab::robustness
