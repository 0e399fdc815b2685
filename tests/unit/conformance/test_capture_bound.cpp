// A bounded capture keeps the run's last connections whole and says how much it let go; an
// unbounded one (conform's) keeps everything.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "conformance/capture.hpp"

namespace mblab::test {
namespace {

using conformance::Capture;
using Kind = conformance::CaptureEvent::Kind;

void connections(Capture& capture, int count) {
    const std::vector<std::uint8_t> bytes(1000, 0x55);
    for (int i = 0; i < count; ++i) {
        capture.on_open({});
        capture.on_sent(bytes);
        capture.on_received(bytes);
        capture.on_close(false);
    }
}

TEST(CaptureBound, KeepsTheLastConnectionsWithinTheBound) {
    constexpr std::size_t kBound = 64 * 1024;
    Capture capture(kBound);
    connections(capture, 1000);
    const auto& events = capture.events();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.front().kind, Kind::Open);
    EXPECT_EQ(events.back().kind, Kind::Close);
    std::size_t kept = 0;
    for (const auto& e : events)
        kept += e.bytes.size();
    EXPECT_LE(kept, kBound);
    EXPECT_GE(kept, kBound / 4);
    EXPECT_EQ(kept + capture.dropped_bytes(), 1000U * 2000U);
}

TEST(CaptureBound, WithoutABoundEverythingIsKept) {
    Capture capture;
    connections(capture, 1000);
    EXPECT_EQ(capture.events().size(), 4000U);
    EXPECT_EQ(capture.dropped_bytes(), 0U);
}

}  // namespace
}  // namespace mblab::test
