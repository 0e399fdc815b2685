#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "client/link.hpp"
#include "device/request_handler.hpp"
#include "support/manual_clock.hpp"

// A device behind in-memory client links, on a manual clock: what a link sends is cut into
// requests by the framing's own framer, served by a RequestHandler (a ReferenceDevice), and the
// answers framed and read back through the client's framer, as over a socket or a serial port
// without either. Waiting on a link moves the clock: a receive that finds nothing advances it by
// its timeout. The device can be made to die on an input, and restarted, as the robustness
// tester's targets do.
namespace mblab::test {

class MemoryLink;

class MemoryDevice {
  public:
    MemoryDevice(device::RequestHandler& handler, protocol::Framing framing, ManualClock& clock);

    // Links opened so far share the device: a new one is a fresh connection (or the line again).
    std::unique_ptr<client::Link> open();
    // From the first request the device's framer cuts (a frame, or bytes it refuses, such as a
    // bad CRC) that `kills` holds for, the device answers nothing on any link, until restart().
    using Kills = std::function<bool(const client::Received& request)>;
    void die_on(Kills kills) { kills_ = std::move(kills); }
    void restart() {
        dead_ = false;
        ++restarts_;
    }
    bool dead() const { return dead_; }
    std::size_t restarts() const { return restarts_; }
    std::size_t opened() const { return opened_; }
    // Every request ADU the device took, as hex ("01 03 00 00 00 01 84 0A"), in order.
    const std::vector<std::string>& requests() const { return requests_; }
    ManualClock& clock() { return clock_; }
    protocol::Framing framing() const { return framing_; }

  private:
    friend class MemoryLink;
    // One request from `link`: served when it is a whole frame, the answer queued on the link.
    void serve(MemoryLink& link, const client::Received& request);

    device::RequestHandler& handler_;
    protocol::Framing framing_;
    ManualClock& clock_;
    Kills kills_;
    bool dead_ = false;
    std::size_t restarts_ = 0;
    std::size_t opened_ = 0;
    std::vector<std::string> requests_;
};

}  // namespace mblab::test
