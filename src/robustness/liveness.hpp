#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "client/link.hpp"
#include "conformance/serving_check.hpp"
#include "robustness/case_links.hpp"
#include "robustness/run_clock.hpp"

// The liveness oracle: is the device still serving after a case? The known-good read of
// conformance/serving_check (FC 03 of one register that answered during reconnaissance, its data
// answer required) on the link the run's links give the check (a fresh connection over
// Modbus/TCP, the quiet line on a serial line), and the same on a link opened before the case
// where there is one. Closing a connection is the device's right; not
// answering, refusing every connection or answering the known-good read wrongly is not. Unit 0 is
// broadcast and never answered on a line [SER 2.1], so it is never the address asked.
namespace mblab::robustness {

struct Liveness {
    bool alive = true;
    std::string reason;  // why the device is judged dead
    std::chrono::milliseconds waited{0};
};

class LivenessOracle {
  public:
    LivenessOracle(CaseLinks& links, std::uint8_t unit, std::uint16_t address,
                   std::chrono::milliseconds timeout, RunClock clock = {});

    Liveness check();
    // check() until the device is alive or `patience` has passed: after a restart.
    Liveness wait_alive(std::chrono::milliseconds patience);
    // Opens the link that the next check asks on as an already-open one, where there is one.
    void open_bystander();
    // Holding register `address` read on the check's link; nullopt when it is not answered
    // with its value.
    std::optional<std::uint16_t> read_register(std::uint16_t address);
    // The device served a fresh connection only once the bystander was closed: it serves one
    // connection at a time, and the bystander is no longer kept.
    bool one_at_a_time() const { return one_at_a_time_; }

  private:
    // The known-good read of `address` on `link`, asked by the one serving check.
    conformance::ServingAnswer ask(client::Link& link, std::uint16_t address);
    // The check's link, opening tried again over about a second and a half: a device with one
    // connection slot may still be freeing it.
    client::Link* reach(client::LinkError& error);

    CaseLinks& links_;
    RunClock clock_;
    bool one_at_a_time_ = false;
    std::uint8_t unit_;
    std::uint16_t address_;
    std::chrono::milliseconds timeout_;
    std::uint16_t transaction_ = 0x7000;
};

}  // namespace mblab::robustness
