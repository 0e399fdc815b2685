#pragma once

#include <cstdint>
#include <string>

#include "protocol/adu.hpp"
#include "robustness/fuzz_run.hpp"
#include "robustness/recon.hpp"

// A device killed by a reconnaissance probe (a write it must refuse, a read of one register): the
// run's finding before any case, with the probe alone as its reproducer. The device answered the
// known-good read before the probe and not after it, so the probe is what killed it.
namespace mblab::robustness {

// The run's result for `recon`, whose killed_by is set: no case run, the probe as the finding.
FuzzResult probe_finding(const Recon& recon, const std::string& target, std::uint64_t seed,
                         protocol::Framing framing);

}  // namespace mblab::robustness
