#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

// Reconnaissance: what the device serves, learned with plain requests before any bad one, so the
// cases aim at code that runs and the liveness check asks something the device answers.
namespace mblab::robustness {

struct Recon {
    std::uint8_t unit = 1;
    std::vector<std::uint8_t> served;      // function codes answered other than with exception 01
    std::vector<std::uint8_t> not_served;  // answered 01
    std::vector<std::uint8_t> silent;      // not answered at all
    std::uint16_t check_address = 0;       // a holding register FC 03 reads: the liveness check
    std::uint16_t max_read = 125;          // the largest FC 03 quantity answered there
    bool answers_unit_0 = false;
    bool answers_unit_255 = false;
    std::string source = "probed";  // or the DUT file that declared unit and max_read

    bool serves(std::uint8_t function) const;
};

// One request and its answer's PDU: nullopt when none came (timeout, closed connection).
using Ask = std::function<std::optional<std::vector<std::uint8_t>>(
    std::uint8_t unit, std::span<const std::uint8_t> pdu)>;

struct ReconOptions {
    std::uint8_t unit = 1;
    bool allow_writes = false;
    // Declared facts that replace the probed ones (from --dut).
    std::optional<std::uint16_t> max_read;
    std::optional<std::uint16_t> check_address;
};

// The request probing `function` without changing anything: a write that the device must
// refuse (quantity 0, a coil value other than 0000/FF00) unless writes are allowed, where it is
// the plain request. nullopt for codes not probed.
std::optional<std::vector<std::uint8_t>> probe_request(std::uint8_t function, bool allow_writes);

// Fails with one line when no holding register answers FC 03 (nothing to check liveness with).
std::optional<std::string> reconnoitre(const Ask& ask, const ReconOptions& options, Recon& out);

}  // namespace mblab::robustness
