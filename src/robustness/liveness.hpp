#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "client/link.hpp"
#include "client/target.hpp"
#include "conformance/session.hpp"

// The liveness oracle: is the device still serving after a case? A known-good read (FC 03 of one
// register that answered during reconnaissance) on a fresh connection, and the same on a
// connection opened before the case. Closing a connection is the device's right; not answering,
// refusing every connection or answering the known-good read wrongly is not.
namespace mblab::robustness {

// The known-good read: FC 03 of one register at `address`.
std::array<std::uint8_t, 5> known_good_read(std::uint16_t address);
// Whether `pdu` is its answer: FC 03 with the one register.
bool answers_known_good(std::span<const std::uint8_t> pdu);

struct Liveness {
    bool alive = true;
    std::string reason;  // why the device is judged dead
    std::chrono::milliseconds waited{0};
};

class LivenessOracle {
  public:
    LivenessOracle(const client::Target& target, std::uint8_t unit, std::uint16_t address,
                   std::chrono::milliseconds timeout, client::LinkObserver* observer);

    Liveness check();
    // check() until the device is alive or `patience` has passed: after a restart.
    Liveness wait_alive(std::chrono::milliseconds patience);
    // Opens the connection that the next check asks on as an already-open one.
    void open_bystander();
    // Holding register `address` read on a fresh connection; nullopt when it is not answered
    // with its value.
    std::optional<std::uint16_t> read_register(std::uint16_t address);
    void close();
    // The device served a fresh connection only once the bystander was closed: it serves one
    // connection at a time, and the bystander is no longer kept.
    bool one_at_a_time() const { return one_at_a_time_; }

  private:
    enum class Outcome : std::uint8_t { Good, Closed, Silent, Wrong };
    Outcome ask(conformance::Session& session, std::string& detail);

    conformance::Session fresh_;
    conformance::Session bystander_;
    bool bystander_open_ = false;
    bool one_at_a_time_ = false;
    std::uint8_t unit_;
    std::uint16_t address_;
    std::chrono::milliseconds timeout_;
    std::uint16_t transaction_ = 0x7000;
};

}  // namespace mblab::robustness
