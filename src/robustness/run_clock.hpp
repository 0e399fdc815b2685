#pragma once

#include <chrono>
#include <functional>
#include <thread>

// The time a robustness run keeps: the steady clock and real sleeps, or a test's manual clock,
// which moves only when the run waits, so a run's timing is tested without waiting for it.
namespace mblab::robustness {

using Clock = std::chrono::steady_clock;

struct RunClock {
    std::function<Clock::time_point()> now = [] { return Clock::now(); };
    std::function<void(Clock::duration)> sleep = [](Clock::duration span) {
        std::this_thread::sleep_for(span);
    };

    std::chrono::milliseconds since(Clock::time_point start) const {
        return std::chrono::duration_cast<std::chrono::milliseconds>(now() - start);
    }
    void sleep_until(Clock::time_point at) const {
        const auto from = now();
        if (at > from) sleep(at - from);
    }
};

}  // namespace mblab::robustness
