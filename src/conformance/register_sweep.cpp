#include <fmt/core.h>

#include <algorithm>

#include "conformance/block_reads.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"

// CTP 7.5.2: read every count from offset 0, then the whole memory in maximal blocks, then
// shrinking reads that end at the last register. Every answer must carry the right length field,
// byte count and number of registers, and none may be an exception.
namespace mblab::conformance {

namespace {

std::vector<BlockRead> sweep_reads(std::uint32_t registers, std::uint16_t max_read) {
    const auto max = static_cast<std::uint32_t>(std::min<std::uint32_t>(max_read, registers));
    std::vector<BlockRead> reads;
    auto add = [&](std::uint32_t offset, std::uint32_t count, const std::string& phase) {
        reads.push_back(
            {static_cast<std::uint16_t>(offset), static_cast<std::uint16_t>(count), phase});
    };
    const std::string first = "phase 1 (growing reads at 0000)";
    for (std::uint32_t count = 1; count <= max; ++count)
        add(0, count, first);
    const std::string second = fmt::format("phase 2 (blocks of {})", max);
    for (std::uint32_t offset = 0; offset < registers; offset += max) {
        add(offset, std::min(max, registers - offset), second);
    }
    const std::string third = "phase 3 (shrinking reads to the last register)";
    for (std::uint32_t count = max; count >= 1; --count)
        add(registers - count, count, third);
    return reads;
}

}  // namespace

Outcome run_register_sweep(Session& session, const Case& c) {
    (void)c;
    const Dut& dut = session.dut();
    auto reads = sweep_reads(*dut.registers, dut.max_read);
    auto run = read_blocks(session, reads, "register sweep",
                           [](const BlockRead&, protocol::RegisterView) { return true; });
    if (run.failure) return *run.failure;
    return Outcome{
        Verdict::Pass,
        fmt::format("{} reads of up to {} registers over {} registers, {}", reads.size(),
                    std::min<std::uint32_t>(dut.max_read, *dut.registers), *dut.registers, run.how),
        {}};
}

}  // namespace mblab::conformance
