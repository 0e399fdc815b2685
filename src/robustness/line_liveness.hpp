#pragma once

#include <chrono>
#include <cstdint>

#include "client/link.hpp"
#include "robustness/liveness.hpp"

// The liveness oracle on a serial line (or RTU over TCP), where there is one link and no fresh
// connection to ask on: once the line has been quiet for at least t3.5, a known-good read (FC 03
// of one register) to the device's own address, asked again once before silence counts. Unit 0
// is broadcast and never answered on a line [SER 2.1], so it is never the address asked.
namespace mblab::robustness {

class LineOracle {
  public:
    LineOracle(std::uint8_t unit, std::uint16_t address, std::chrono::milliseconds timeout,
               std::chrono::milliseconds quiet);

    // Reads and drops whatever the device still sends (late answers to the case), then asks.
    Liveness check(client::Link& link);

  private:
    enum class Outcome : std::uint8_t { Good, Closed, Silent };
    Outcome ask(client::Link& link, std::string& detail);
    void drain(client::Link& link);

    std::uint8_t unit_;
    std::uint16_t address_;
    std::chrono::milliseconds timeout_;
    std::chrono::milliseconds quiet_;
};

}  // namespace mblab::robustness
