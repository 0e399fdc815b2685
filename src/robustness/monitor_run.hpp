#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "client/link.hpp"
#include "robustness/case_links.hpp"
#include "robustness/monitor_core.hpp"

// The essential-function monitor on a thread and a connection of its own, beside the robustness
// run: MonitorCore's requests sent on the link, its answers read back, the link opened again
// when the device closes it (that cycle missed). Over Modbus/TCP (and mbaps://) only: a serial
// line has one link, which the run's cases hold.
namespace mblab::robustness {

class MonitorRun {
  public:
    MonitorRun(MonitorSpec spec, Dial dial);
    ~MonitorRun();
    MonitorRun(const MonitorRun&) = delete;
    MonitorRun& operator=(const MonitorRun&) = delete;

    void start();
    void stop();
    // The cycles so far (a copy: the thread goes on adding).
    std::vector<MonitorCycle> cycles() const;
    // Waits until a cycle started at or after `since` holds, or `patience` has passed; whether one
    // did.
    bool wait_held(Clock::time_point since, std::chrono::milliseconds patience) const;

  private:
    void loop();

    Dial dial_;
    mutable std::mutex mutex_;
    MonitorCore core_;
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace mblab::robustness
