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

// Asks for what to do with each answer's registers, in the order of the reads: true to go on,
// false to stop early.
using BlockSink = std::function<bool(const BlockRead&, protocol::RegisterView)>;

struct BlockRun {
    std::optional<Outcome> failure;  // nothing when every answer was right or the sink stopped
    std::string how;                 // "one request at a time", "pipelined 16 deep", ...
};

// Sends the reads and checks every answer is "{tid} 00 00 {len} {unit} 03 {2n} XX*2n" (CTP
// 7.5.2.6). With the session's pipeline depth at 1 (the default) the reads go as the policy
// writes them: transaction id 0, one outstanding. Deeper, they are numbered, answers are paired
// by transaction id in whatever order they come ([TCPG]), and an exception 06 (busy) answer is
// back-pressure: the depth is lowered, the read sent again after a pause, and `how` says so.
BlockRun read_blocks(Session& session, const std::vector<BlockRead>& reads, std::string_view what,
                     const BlockSink& sink);

}  // namespace mblab::conformance
