#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "conformance/session.hpp"
#include "conformance/verdict.hpp"
#include "protocol/register_view.hpp"

namespace mblab::conformance {

// One FC 03 read of the register sweep or the SEMI scan.
struct BlockRead {
    std::uint16_t offset = 0;
    std::uint16_t count = 0;
    std::string phase;  // "phase 2 (blocks of 125)", for the failure report
};

// Asks for what to do with each answer's registers: true to go on, false to stop early.
using BlockSink = std::function<bool(const BlockRead&, protocol::RegisterView)>;

// Sends the reads with up to the session's pipeline depth in flight, and checks every answer is
// "00 00 00 00 {len} {unit} 03 {2n} XX*2n" (seed 000 7.5.2.6). Returns the failure, if any;
// nothing when every answer was right or the sink stopped the reads.
std::optional<Outcome> read_blocks(Session& session, const std::vector<BlockRead>& reads,
                                   std::string_view what, const BlockSink& sink);

}  // namespace mblab::conformance
