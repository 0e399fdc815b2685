#include "server/behaviour_timer.hpp"

#include <algorithm>
#include <chrono>

namespace mblab::server {

BehaviourTimer::BehaviourTimer(asio::io_context& io, device::ReferenceDevice& device)
    : timer_(io), device_(device) {}

void BehaviourTimer::start() {
    stopped_ = false;
    arm();
}

void BehaviourTimer::stop() {
    stopped_ = true;
    timer_.cancel();
}

void BehaviourTimer::arm() {
    const auto due = device_.behaviours().deadline();
    if (due == std::chrono::steady_clock::time_point::max()) return;
    timer_.expires_at(std::max(due, std::chrono::steady_clock::time_point{}));
    timer_.async_wait([this](const asio::error_code& ec) {
        if (ec || stopped_) return;
        device_.behaviours().advance(std::chrono::steady_clock::now(),
                                     std::chrono::system_clock::now());
        arm();
    });
}

}  // namespace mblab::server
