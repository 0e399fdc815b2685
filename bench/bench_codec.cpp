// Codec and framer throughput. Every benchmark also counts heap allocations made inside its
// timed loop ("allocs"): the protocol hot paths promise none, so anything but 0 is a defect.
#include <benchmark/benchmark.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "protocol/adu_writer.hpp"
#include "protocol/ascii_framer.hpp"
#include "protocol/cursor.hpp"
#include "protocol/mbap_framer.hpp"
#include "protocol/response.hpp"
#include "protocol/rtu_framer.hpp"

namespace {
std::atomic<std::size_t> g_allocations{0};

void* counted_alloc(std::size_t size) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) {
    return counted_alloc(size);
}
void* operator new[](std::size_t size) {
    return counted_alloc(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
    return operator new(size, tag);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}

namespace mblab::protocol {
namespace {

// Counts allocations between construction and report(); put around the timed loop only.
class AllocationProbe {
  public:
    AllocationProbe() : start_(g_allocations.load()) {}
    void report(benchmark::State& state) const {
        state.counters["allocs"] = static_cast<double>(g_allocations.load() - start_);
    }

  private:
    std::size_t start_;
};

// (a) A read holding registers response of 125 registers, encoded then decoded.
void BM_Fc03Response125EncodeDecode(benchmark::State& state) {
    std::array<std::uint8_t, 250> registers{};
    for (std::size_t i = 0; i < registers.size(); ++i)
        registers[i] = static_cast<std::uint8_t>(i);
    const Response response =
        ReadRegistersResponse{FunctionCode::ReadHoldingRegisters, RegisterView(registers)};
    std::array<std::uint8_t, limits::kMaxPdu> pdu{};
    std::size_t size = 0;
    AllocationProbe probe;
    for (auto _ : state) {
        WriteCursor out(pdu);
        if (!encode_response(response, out)) state.SkipWithError("encode failed");
        size = out.size();
        auto decoded = decode_response(std::span(pdu).first(size));
        if (!decoded) state.SkipWithError("decode failed");
        benchmark::DoNotOptimize(decoded);
    }
    probe.report(state);
    state.SetItemsProcessed(state.iterations());
    state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(size));
}
BENCHMARK(BM_Fc03Response125EncodeDecode);

// About 64 KiB of back-to-back frames made by `write` (an ADU writer bound to its arguments).
template <class Write>
std::vector<std::uint8_t> stream_of(Write write) {
    std::vector<std::uint8_t> stream;
    std::array<std::uint8_t, 600> adu{};
    for (std::uint16_t i = 0; stream.size() < 64 * 1024 - adu.size(); ++i) {
        const std::size_t size = write(i, adu);
        stream.insert(stream.end(), adu.begin(), adu.begin() + static_cast<std::ptrdiff_t>(size));
    }
    return stream;
}

// Feeds the whole stream in chunks of state.range(0) bytes per iteration.
template <class Framer>
void run_framer(benchmark::State& state, Framer framer, const std::vector<std::uint8_t>& stream) {
    const auto chunk = static_cast<std::size_t>(state.range(0));
    std::int64_t frames = 0;
    AllocationProbe probe;
    for (auto _ : state) {
        for (std::size_t at = 0; at < stream.size(); at += chunk) {
            auto rest = std::span(stream).subspan(at, std::min(chunk, stream.size() - at));
            for (;;) {
                std::size_t consumed = 0;
                const FrameEvent event = framer.feed(rest, consumed);
                rest = rest.subspan(consumed);
                if (event.status == FrameStatus::NeedMore) break;
                frames += event.status == FrameStatus::Frame;
                benchmark::DoNotOptimize(event.pdu.data());
            }
        }
    }
    probe.report(state);
    state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(stream.size()));
    state.counters["frames/s"] =
        benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["frames/iter"] =
        static_cast<double>(frames) / static_cast<double>(state.iterations());
}

constexpr std::array<std::uint8_t, 5> kFc03Request = {0x03, 0x00, 0x6B, 0x00, 0x7D};

// (b) MBAP framer over FC 03 requests.
void BM_MbapFramerFc03Requests(benchmark::State& state) {
    const auto stream = stream_of([](std::uint16_t i, std::span<std::uint8_t> out) {
        return write_mbap_adu(MbapHeader{i, 0, 0, 1}, kFc03Request, out);
    });
    run_framer(state, MbapFramer{}, stream);
}
BENCHMARK(BM_MbapFramerFc03Requests)->Arg(1)->Arg(64 * 1024);

// (c) RTU framer over FC 03 requests, and over 125-register FC 03 responses (255 bytes each).
void BM_RtuFramerFc03Requests(benchmark::State& state) {
    const auto stream = stream_of([](std::uint16_t i, std::span<std::uint8_t> out) {
        return write_rtu_adu(static_cast<std::uint8_t>(1 + i % 247), kFc03Request, out);
    });
    run_framer(state, RtuFramer{Direction::Request}, stream);
}
BENCHMARK(BM_RtuFramerFc03Requests)->Arg(1)->Arg(64 * 1024);

void BM_RtuFramerFc03Responses125(benchmark::State& state) {
    std::array<std::uint8_t, 252> pdu{};
    pdu[0] = 0x03;
    pdu[1] = 250;
    const auto stream = stream_of([&pdu](std::uint16_t i, std::span<std::uint8_t> out) {
        return write_rtu_adu(static_cast<std::uint8_t>(1 + i % 247), pdu, out);
    });
    run_framer(state, RtuFramer{Direction::Response}, stream);
}
BENCHMARK(BM_RtuFramerFc03Responses125)->Arg(1)->Arg(64 * 1024);

void BM_AsciiFramerFc03Requests(benchmark::State& state) {
    const auto stream = stream_of([](std::uint16_t i, std::span<std::uint8_t> out) {
        return write_ascii_adu(static_cast<std::uint8_t>(1 + i % 247), kFc03Request, out);
    });
    run_framer(state, AsciiFramer{}, stream);
}
BENCHMARK(BM_AsciiFramerFc03Requests)->Arg(1)->Arg(64 * 1024);

}  // namespace
}  // namespace mblab::protocol

BENCHMARK_MAIN();
