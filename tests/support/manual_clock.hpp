#pragma once

#include <chrono>

// Time for sans-I/O tests: it moves only when the test says so. Its time points are
// steady_clock's, so code that takes `now` from steady_clock takes them unchanged.
namespace mblab::test {

class ManualClock {
  public:
    using time_point = std::chrono::steady_clock::time_point;

    time_point now() const { return now_; }
    void advance(std::chrono::steady_clock::duration by) { now_ += by; }
    // Moves to `at`, never back.
    void advance_to(time_point at) {
        if (at > now_) now_ = at;
    }
    // Time since the clock was made, for messages.
    std::chrono::milliseconds elapsed() const {
        return std::chrono::duration_cast<std::chrono::milliseconds>(now_ - kStart);
    }

  private:
    // Away from the epoch: some code reads a zero time point as "never".
    static constexpr time_point kStart = time_point{} + std::chrono::hours(1);
    time_point now_ = kStart;
};

}  // namespace mblab::test
