#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "conformance/block_reads.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"

// CTP 7.13.2: read the register memory in blocks of up to 125 until 0x5345 0x4D49 0x5F72
// ("SE", "MI" and their zero-sum checksum) are found in consecutive registers.
namespace mblab::conformance {

namespace {
constexpr std::array<std::uint16_t, 3> kSignature = {0x5345, 0x4D49, 0x5F72};
constexpr std::uint32_t kAddressSpace = 65536;
}  // namespace

Outcome run_semi_scan(Session& session, const Case& c) {
    const Dut& dut = session.dut();
    const auto block =
        static_cast<std::uint32_t>(std::min<std::int64_t>(dut.max_read, param(c, "block")));
    const std::uint32_t end = dut.registers.value_or(kAddressSpace);
    std::vector<BlockRead> reads;
    for (std::uint32_t offset = 0; offset < end; offset += block) {
        reads.push_back({static_cast<std::uint16_t>(offset),
                         static_cast<std::uint16_t>(std::min(block, end - offset)),
                         fmt::format("blocks of {}", block)});
    }
    // The signature may straddle two blocks, so matching runs over the register stream.
    std::size_t matched = 0;
    std::optional<std::uint32_t> found_at;
    auto run = read_blocks(session, reads, "SEMI signature scan",
                           [&](const BlockRead& read, protocol::RegisterView values) {
                               for (std::size_t i = 0; i < values.size(); ++i) {
                                   if (values[i] == kSignature[matched]) {
                                       ++matched;
                                   } else {
                                       matched = values[i] == kSignature[0] ? 1 : 0;
                                   }
                                   if (matched == kSignature.size()) {
                                       found_at = read.offset + i + 1 - kSignature.size();
                                       return false;
                                   }
                               }
                               return true;
                           });
    if (run.failure) return *run.failure;
    if (!found_at) {
        return Outcome{Verdict::Fail,
                       fmt::format("5345 4D49 5F72 not found in registers 0000-{:04X}; scan {}",
                                   end - 1, run.how),
                       {}};
    }
    return Outcome{Verdict::Pass,
                   fmt::format("signature at register {:04X}; scan {}", *found_at, run.how),
                   {}};
}

}  // namespace mblab::conformance
