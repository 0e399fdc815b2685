#include "robustness/monitor_run.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <algorithm>

namespace mblab::robustness {

namespace {

// When the answer just read arrived: the kernel's time of the connection's last data (TCP_INFO,
// to the millisecond) rather than the time the thread read it. On a machine whose cores the run
// itself keeps busy, the monitor's thread can wake 100 ms after an answer that came in 1 ms;
// the device is judged on when it answered.
Clock::time_point arrived(const client::Link& link, Clock::time_point read_at) {
    const int fd = link.tcp_descriptor();
    tcp_info info{};
    socklen_t size = sizeof info;
    if (fd < 0 || getsockopt(fd, IPPROTO_TCP, TCP_INFO, &info, &size) != 0) return read_at;
    return read_at - std::chrono::milliseconds(info.tcpi_last_data_recv);
}

}  // namespace

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
    // Gives the core a frame the connection read within `wait` (a frame only part come stays for
    // the next call); false when none came.
    const auto take = [&](std::chrono::milliseconds wait) {
        auto answer = link->next_frame(wait);
        std::lock_guard lock(mutex_);
        if (answer.status == client::ReceiveStatus::Frame) {
            core_.received(answer.bytes, arrived(*link, Clock::now()));
            return true;
        }
        if (answer.status != client::ReceiveStatus::Timeout) {
            link.reset();
            core_.connection_lost(Clock::now());
        }
        return false;
    };
    while (!stopping_) {
        // What came while the thread was away is read before poll() judges the budget.
        while (link && take(std::chrono::milliseconds(0))) {
        }
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
        take(wait);
    }
}

}  // namespace mblab::robustness
