#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "client/target.hpp"
#include "conformance/provenance.hpp"
#include "protocol/result.hpp"
#include "robustness/recon.hpp"

// `mblab scan`: what a device answers, learned with requests that change nothing (reads, the
// FC 08 return query data echo, device identification, the writes the device must refuse that
// reconnaissance sends), so that the declarations `mblab conform --dut` needs can be written
// for the user to check instead of typed from a manual.
namespace mblab::robustness {

struct ScanOptions {
    std::vector<std::uint8_t> units;  // tried in this order; the first that answers is scanned
    // On a serial line unit 0 is the broadcast and 248..255 are no device's address: requests to
    // them are not sent (nothing can answer them).
    bool line = false;
};

// FC 08 sub-function 00 (return query data) with more and more data words.
struct EchoScan {
    bool asked = false;
    std::uint16_t echoed = 0;  // the most data words echoed whole (0: not even one)
    // When `echoed` is short of what a PDU holds: what came back for one word more; nullopt
    // when nothing did.
    std::optional<std::uint8_t> refusal;  // the exception code
    bool data_refused = false;            // an answer that was neither the echo nor an exception
};

struct DeviceScan {
    std::vector<std::uint8_t> tried;
    std::vector<std::uint8_t> answering;  // answered FC 03 with data or an exception
    Recon recon;                          // of the scanned unit: served function codes, max_read
    std::string recon_failure;            // when no holding register answered FC 03
    // Each table's run of addresses that answered single reads, then answered read whole.
    std::array<std::optional<AddressRange>, kTableCount> tables{};
    EchoScan echo;
    bool object_messaging = false;                // FC 5B get attribute answered other than with 01
    bool object_messaging_silent = false;         // ... or not answered at all
    std::optional<std::uint16_t> semi_signature;  // where 5345 4D49 5F72 starts
    std::optional<std::uint16_t> file_number;     // FC 14 of file 1, record 0 answered data
    std::optional<std::uint16_t> fifo_address;    // FC 18 at 0 answered data
    conformance::DeviceIdentity identity;
    std::size_t requests = 0;
};

// The most FC 08/00 data words a PDU holds: 253 bytes less the function code and the
// sub-function ([APP] 4.1).
inline constexpr std::uint16_t kMaxEchoWords = 125;

// Asks `ask` what the units of `options` answer, then scans the first that does. The error is
// one line saying what was tried when no unit answered.
protocol::Result<DeviceScan, std::string> scan_device(const Ask& ask, const ScanOptions& options);

// scan_device over a connection to `target` (TLS already attached for mbaps://), then device
// identification (FC 2B/0E, basic) of the scanned unit. Errors: the target cannot be reached, or
// no unit answered.
protocol::Result<DeviceScan, std::string> scan_target(const client::Target& target,
                                                      const ScanOptions& options,
                                                      std::chrono::milliseconds timeout);

// "1, 255 or 0", "1-247".
std::string units_text(const std::vector<std::uint8_t>& units, const char* last_joint);

}  // namespace mblab::robustness
