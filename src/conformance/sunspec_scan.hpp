#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "device/sunspec_model.hpp"

// Reading a SunSpec device: the `SunS` marker, then the chain of models after it, each model
// decoded by its definition (SunSpec Information Model Specification v1.0, "Device Modbus Map":
// the marker at 40000, 0 or 50000, each model's ID and L, the end model 0xFFFF).
namespace mblab::conformance {

// Reads `count` holding registers at `address` (FC 03).
using RegisterReader = std::function<client::CallResult<std::vector<std::uint16_t>>(
    std::uint16_t address, std::uint16_t count)>;

// The bases looked at, in order.
inline constexpr std::uint16_t kSunSpecBases[] = {40000, 0, 50000};
// At most this many registers in one read ([APP] 6.3).
inline constexpr std::uint16_t kMaxRegistersPerRead = 125;

struct SunSpecPointReading {
    const device::SunSpecPoint* point = nullptr;
    // Where the point is: "" in the model's top group, "curve[1].pt[2]" in repeating groups.
    std::string group = {};
    std::uint32_t address = 0;
    std::vector<std::uint16_t> words = {};
    bool implemented = true;
    // The value with its scale factor applied; none for strings, pads, addresses, a point not
    // implemented or whose scale factor is not.
    std::optional<double> value = {};
    std::optional<int> scale = {};
};

struct SunSpecModelReading {
    std::uint16_t id = 0;
    std::uint32_t address = 0;                         // of its ID register
    std::uint16_t length = 0;                          // L as the device says
    const device::SunSpecModel* definition = nullptr;  // none: a model id not known
    std::vector<SunSpecPointReading> points = {};
    std::string problem = {};  // why it was not decoded in full
};

struct SunSpecScan {
    std::uint16_t base = 0;
    std::vector<SunSpecModelReading> models = {};
    std::uint32_t end_address = 0;  // of the end model
    // Why the chain stops short of the end model (a header that cannot be read, a model past the
    // last register); empty when it ends as it should. The models before it are kept.
    std::string chain_problem = {};
};

// Finds the marker and reads the whole chain. Fails (one line) when no base holds the marker, or
// when reading it fails other than by an exception; a chain that breaks off is a scan with its
// chain_problem.
protocol::Result<SunSpecScan, std::string> scan_sunspec(
    const RegisterReader& read, const std::map<std::uint16_t, device::SunSpecModel>& models);

// A point's symbol name when its value is one of its symbols.
std::optional<std::string> symbol_name(const device::SunSpecPoint& point, double value);

}  // namespace mblab::conformance
