#pragma once

#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>

#include "device/reference_device.hpp"

// Moves a device's values (its profile's behaviours) from a timer on the server's event loop,
// set to the device's next update: updates run between requests, never inside one, and a device
// with nothing to move costs no wake-up at all.
namespace mblab::server {

class BehaviourTimer {
  public:
    BehaviourTimer(asio::io_context& io, device::ReferenceDevice& device);
    BehaviourTimer(const BehaviourTimer&) = delete;
    BehaviourTimer& operator=(const BehaviourTimer&) = delete;

    // The first update runs at once, so the values hold their start values before any request.
    void start();
    // A completion already queued when the timer is cancelled still runs: the flag stops it.
    void stop();

  private:
    void arm();

    asio::steady_timer timer_;
    device::ReferenceDevice& device_;
    bool stopped_ = false;
};

}  // namespace mblab::server
