#include "robustness/monitor_run.hpp"

#include <algorithm>

namespace mblab::robustness {

MonitorRun::MonitorRun(MonitorSpec spec, Dial dial)
    : dial_(std::move(dial)), core_(spec, Clock::now()) {}

MonitorRun::~MonitorRun() {
    stop();
}

void MonitorRun::start() {
    thread_ = std::thread([this] { loop(); });
}

void MonitorRun::stop() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

std::vector<MonitorCycle> MonitorRun::cycles() const {
    std::lock_guard lock(mutex_);
    return core_.cycles();
}

bool MonitorRun::wait_held(Clock::time_point since, std::chrono::milliseconds patience) const {
    const auto until = Clock::now() + patience;
    while (true) {
        {
            std::lock_guard lock(mutex_);
            const auto& all = core_.cycles();
            if (std::any_of(all.begin(), all.end(),
                            [&](const MonitorCycle& c) { return c.started >= since && c.held(); }))
                return true;
        }
        if (Clock::now() >= until) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

void MonitorRun::loop() {
    std::unique_ptr<client::Link> link;
    while (!stopping_) {
        std::vector<std::uint8_t> request;
        Clock::time_point deadline;
        {
            std::lock_guard lock(mutex_);
            request = core_.poll(Clock::now());
            deadline = core_.deadline();
        }
        if (!request.empty()) {
            client::LinkError error;
            if (!link) {
                auto opened = dial_();
                if (opened) link = std::move(opened.value());
            }
            if (!link || !link->send(request, error)) {
                link.reset();
                std::lock_guard lock(mutex_);
                core_.connection_lost(Clock::now());
                continue;
            }
        }
        // Read until the core's next deadline, in short waits so that stop() is heard.
        const auto wait = std::clamp(
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()),
            std::chrono::milliseconds(1), std::chrono::milliseconds(20));
        if (!link) {
            std::this_thread::sleep_for(wait);
            continue;
        }
        auto answer = link->receive_frame(wait);
        std::lock_guard lock(mutex_);
        if (answer.status == client::ReceiveStatus::Frame) {
            core_.received(answer.bytes, Clock::now());
        } else if (answer.status != client::ReceiveStatus::Timeout) {
            link.reset();
            core_.connection_lost(Clock::now());
        }
    }
}

}  // namespace mblab::robustness
