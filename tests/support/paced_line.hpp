#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

// A serial line in memory as its receiver sees it: each character arrives one character time
// after the last (11 bits at the baud rate, [SER 2.5.1]), and a test can hold byte K back by a
// silence of its choosing. The bytes come out with the time each one's last bit arrived, for a
// sans-IO core on a manual clock.
namespace mblab::test {

class PacedLine {
  public:
    using Clock = std::chrono::steady_clock;

    explicit PacedLine(unsigned baud);

    // 11 bits at the baud rate.
    Clock::duration char_time() const { return char_time_; }

    // The sender starts `bytes` at `start`, or as soon as the bytes before them are out.
    void send(std::span<const std::uint8_t> bytes, Clock::time_point start);
    // Before byte `index` (counted over everything sent) the sender stays silent for `gap`.
    // Set it before sending that byte: a byte's time is fixed when it is sent.
    void gap_before(std::size_t index, Clock::duration gap);

    // When the next byte not yet taken arrives; time_point::max() when none is on its way.
    Clock::time_point next_arrival() const;
    // When the last byte sent arrives.
    Clock::time_point last_arrival() const;
    // The bytes that have arrived by `now` and were not yet taken, each byte with its time.
    struct Arrival {
        std::uint8_t byte;
        Clock::time_point at;
    };
    std::vector<Arrival> take(Clock::time_point now);

  private:
    struct Gap {
        std::size_t index;
        Clock::duration length;
    };

    Clock::duration char_time_;
    std::vector<Gap> gaps_;
    std::deque<Arrival> arrivals_;   // sent, not yet taken
    std::size_t sent_ = 0;           // bytes sent so far
    Clock::time_point line_free_{};  // when the last byte sent has arrived
};

}  // namespace mblab::test
