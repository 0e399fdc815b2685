// What `mblab serve` does for one request in user space, without the socket: an MBAP FC 03 read
// of 125 registers goes into the Modbus/TCP session core, through the shipped reference device,
// and its answer comes out gathered for the send. The server benchmark
// (run_server_bench.sh) measures the same path with the kernel's share; this one isolates the
// part mblab's own code decides, so a change to the protocol, device or session layers shows here.
#include <benchmark/benchmark.h>
#include <sys/uio.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

#include "device/reference_device.hpp"
#include "immediate_host.hpp"
#include "protocol/adu_writer.hpp"
#include "server/mbap_session.hpp"

namespace mblab::server {
namespace {

void BM_SessionFc03x125(benchmark::State& state) {
    auto loaded = device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
    if (!loaded) {
        state.SkipWithError(loaded.error().c_str());
        return;
    }
    auto& device = **loaded;
    ServerStats stats;
    bench::ImmediateHost host;
    const auto now = Clock::now();
    MbapSession session(device, MbapSessionLimits{}, stats, host, now);
    constexpr std::array<std::uint8_t, 5> kPdu{0x03, 0x00, 0x00, 0x00, 0x7D};
    std::array<std::uint8_t, 12> request{};
    std::array<iovec, MbapSession::kMaxGather> out{};
    std::uint16_t transaction = 0;
    std::int64_t answered = 0;
    for (auto _ : state) {
        protocol::write_mbap_adu({++transaction, 0, 0, 1}, kPdu, request);
        session.receive(request, now);
        const std::size_t parts = session.output(now, out);
        std::size_t bytes = 0;
        for (std::size_t i = 0; i < parts; ++i)
            bytes += out[i].iov_len;
        answered += static_cast<std::int64_t>(bytes);
        session.sent(bytes, now);
    }
    if (answered != state.iterations() * 259) state.SkipWithError("an answer was not 259 bytes");
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SessionFc03x125);

}  // namespace
}  // namespace mblab::server

BENCHMARK_MAIN();
