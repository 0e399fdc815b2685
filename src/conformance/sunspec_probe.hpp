#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/client_error.hpp"
#include "conformance/session.hpp"
#include "conformance/sunspec_scan.hpp"
#include "conformance/verdict.hpp"
#include "device/sunspec_model.hpp"

// What the SunSpec suite's cases start from: the device's chain as scanned over the session, by
// the model definitions (the project's own, or the folder MBLAB_SUNSPEC_MODELS names), and
// reads and writes that keep their exchanges for the evidence.
namespace mblab::conformance {

class SunSpecProbe {
  public:
    explicit SunSpecProbe(Session& session);
    SunSpecProbe(const SunSpecProbe&) = delete;
    SunSpecProbe& operator=(const SunSpecProbe&) = delete;

    // Why no case can run (no definitions, no marker, the device not reached); nothing when the
    // scan is there to judge.
    const std::optional<Outcome>& unusable() const { return unusable_; }
    const SunSpecScan& scan() const { return scan_; }
    const std::map<std::uint16_t, device::SunSpecModel>& models() const { return models_; }

    // FC 03.
    client::CallResult<std::vector<std::uint16_t>> read(std::uint32_t address, std::uint16_t count);
    // FC 16 to the device's unit; with `quiet`, to the broadcast address 0 of a serial line,
    // which no answer may follow for that long.
    client::CallResult<bool> write(std::uint32_t address, std::span<const std::uint16_t> values,
                                   std::optional<std::chrono::milliseconds> quiet = {});
    // The point's registers now.
    client::CallResult<std::vector<std::uint16_t>> read(const SunSpecPointReading& point) {
        return read(point.address, point.point->size);
    }

    // Every point of every model with a definition, in address order.
    std::vector<const SunSpecPointReading*> points() const;

    Outcome fail(std::string reason) const;
    Outcome fail(const client::ClientError& error, const std::string& what) const;

  private:
    client::CallResult<std::vector<std::uint8_t>> ask(
        const std::vector<std::uint8_t>& pdu, std::optional<std::chrono::milliseconds> quiet = {});
    client::CallResult<std::vector<std::uint8_t>> ask_once(
        const std::vector<std::uint8_t>& pdu, std::optional<std::chrono::milliseconds> quiet);

    Session& session_;
    std::map<std::uint16_t, device::SunSpecModel> models_;
    SunSpecScan scan_;
    std::optional<Outcome> unusable_;
    std::uint16_t transaction_ = 0;
    std::optional<Exchange> last_;  // the last exchange, the evidence of a failure
};

// "103.W", "160.module[2].DCA": a point as the cases name it.
std::string point_name(std::uint16_t model, const SunSpecPointReading& point);

}  // namespace mblab::conformance
