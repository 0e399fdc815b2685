#include <gtest/gtest.h>

#include "load/histogram.hpp"

namespace mblab::load {
namespace {

using B = LatencyBuckets;

TEST(LoadHistogram, BucketsAreExactBelow128AndWithinOnePart64Above) {
    for (std::uint64_t v = 0; v < 128; ++v) {
        EXPECT_EQ(B::index(v), v);
        EXPECT_EQ(B::upper(B::index(v)), v);
    }
    EXPECT_EQ(B::index(128), 128U);
    EXPECT_EQ(B::index(129), 128U);
    EXPECT_EQ(B::index(130), 129U);
    EXPECT_EQ(B::upper(128), 129U);
    EXPECT_EQ(B::index(B::kMaxValue), B::kCount - 1);
    EXPECT_EQ(B::index(std::uint64_t{1} << 40), B::kCount - 1);  // clamped
    std::size_t previous = 0;
    for (std::uint64_t v = 1; v < (std::uint64_t{1} << 24); v = v * 21 / 20 + 1) {
        const std::size_t i = B::index(v);
        EXPECT_GE(i, previous) << v;
        EXPECT_GE(B::upper(i), v) << v;
        EXPECT_LE(B::upper(i) - v, v / 64) << v;
        if (i > 0) {
            EXPECT_LT(B::upper(i - 1), v) << v;
        }
        previous = i;
    }
}

TEST(LoadHistogram, PercentilesOfAKnownSpread) {
    LatencyHistogram histogram;
    for (std::uint64_t v = 1; v <= 10000; ++v)
        histogram.record(v);
    LatencySnapshot snapshot;
    histogram.snapshot_into(snapshot);
    EXPECT_EQ(snapshot.count(), 10000U);
    EXPECT_EQ(snapshot.max(), 10000U);
    auto near = [](std::uint64_t got, std::uint64_t want) {
        return got >= want && got <= want + want / 64;
    };
    EXPECT_PRED2(near, snapshot.percentile(0.50), 5000U);
    EXPECT_PRED2(near, snapshot.percentile(0.90), 9000U);
    EXPECT_PRED2(near, snapshot.percentile(0.99), 9900U);
    // 9990's bucket reaches 10111, past the largest value seen.
    EXPECT_EQ(B::upper(B::index(9990)), 10111U);
    EXPECT_EQ(snapshot.percentile(0.999), 10000U);
    EXPECT_EQ(snapshot.percentile(1.0), 10000U);  // never past the largest value seen
    EXPECT_EQ(LatencySnapshot().percentile(0.5), 0U);
}

TEST(LoadHistogram, SnapshotsMergeAndSubtract) {
    LatencyHistogram a;
    LatencyHistogram b;
    a.record(10);
    a.record(20);
    b.record(1000);
    LatencySnapshot merged;
    a.snapshot_into(merged);
    b.snapshot_into(merged);
    EXPECT_EQ(merged.count(), 3U);
    EXPECT_EQ(merged.max(), 1000U);
    EXPECT_EQ(merged.percentile(0.5), 20U);

    LatencySnapshot before;
    a.snapshot_into(before);
    a.record(30);
    a.record(30);
    LatencySnapshot after;
    a.snapshot_into(after);
    const LatencySnapshot interval = after.since(before);
    EXPECT_EQ(interval.count(), 2U);
    EXPECT_EQ(interval.percentile(0.5), 30U);
}

}  // namespace
}  // namespace mblab::load
