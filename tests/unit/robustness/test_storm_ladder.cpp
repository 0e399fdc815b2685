// A storm's rung without I/O: what is due when, on a manual clock; and the ladders --ladder takes.
#include <gtest/gtest.h>

#include "robustness/storm_core.hpp"
#include "robustness/storm_ladder.hpp"
#include "support/manual_clock.hpp"

namespace mblab::robustness {
namespace {

using namespace std::chrono_literals;
using Do = StormAction::Do;

std::string actions(const std::vector<StormAction>& list) {
    std::string out;
    for (const auto& a : list) {
        static constexpr const char* kNames[] = {"open-stream", "send", "open-close",
                                                 "open-slow-reader", "open-half-open"};
        out += std::string(kNames[static_cast<int>(a.what)]) + "x" + std::to_string(a.count) + " ";
    }
    return out;
}

TEST(StormCore, Fc03OpensItsStreamThenSendsWhatIsDueInOneGo) {
    test::ManualClock clock;
    StormCore core(StormKind::Fc03, 1000, clock.now(), 1000ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "open-streamx1 ");
    core.opened(true);
    clock.advance(5ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "sendx5 ");
    core.sent(5);
    core.answered(4);
    // A turn that came late sends the backlog at once: the pace is kept over the rung.
    clock.advance(20ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "sendx20 ");
    core.sent(20);
    EXPECT_EQ(core.rung().sent, 25U);
    EXPECT_EQ(core.rung().answered, 4U);
    EXPECT_EQ(core.rung().reconnects, 0U);
}

TEST(StormCore, Fc03ReopensAClosedStreamAtMostTenTimesASecond) {
    test::ManualClock clock;
    StormCore core(StormKind::Fc03, 100, clock.now(), 1000ms);
    core.poll(clock.now());
    core.opened(true);
    clock.advance(50ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "sendx5 ");
    core.sent(5);
    core.stream_lost();
    // The device closed it 50 ms after it opened: the next open waits for 100 ms since the last.
    clock.advance(10ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "");
    clock.advance(40ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "open-streamx1 sendx5 ");
    core.opened(true);
    core.sent(5);
    EXPECT_EQ(core.rung().reconnects, 1U);
    core.stream_lost();
    clock.advance(100ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "open-streamx1 sendx10 ");
    core.opened(false);  // refused: nothing sent, tried again on the next turn
    clock.advance(100ms);
    EXPECT_EQ(actions(core.poll(clock.now())), "open-streamx1 sendx20 ");
}

TEST(StormCore, ConnectionStormsAskForEachConnectionOnceUntilTheRungEnds) {
    for (auto [kind, what] : {std::pair{StormKind::Opens, "open-close"},
                              std::pair{StormKind::SlowReaders, "open-slow-reader"},
                              std::pair{StormKind::HalfOpen, "open-half-open"}}) {
        test::ManualClock clock;
        const auto begin = clock.now();
        StormCore core(kind, 20, begin, 500ms);
        EXPECT_EQ(actions(core.poll(clock.now())), "");
        clock.advance(49ms);
        EXPECT_EQ(actions(core.poll(clock.now())), "");
        clock.advance(1ms);
        EXPECT_EQ(actions(core.poll(clock.now())), std::string(what) + "x1 ");
        EXPECT_EQ(actions(core.poll(clock.now())), "");  // asked for already
        clock.advance(150ms);
        EXPECT_EQ(actions(core.poll(clock.now())), std::string(what) + "x3 ");
        core.opened(true);
        core.opened(true);
        core.opened(false);
        clock.advance(300ms);
        EXPECT_TRUE(core.over(clock.now()));
        EXPECT_EQ(actions(core.poll(clock.now())), "");
        const auto rung = core.finish(clock.now());
        EXPECT_EQ(rung.kind, kind);
        EXPECT_EQ(rung.opened, 2U);
        EXPECT_EQ(rung.refused, 1U);
        EXPECT_EQ(rung.end - rung.begin, 500ms);
    }
}

TEST(StormCore, PhaseNames) {
    EXPECT_EQ(storm_phase_name(StormKind::Fc03, 100), "storm 100/s");
    EXPECT_EQ(storm_phase_name(StormKind::Opens, 2.5), "storm opens 2.5/s");
    EXPECT_EQ(storm_phase_name(StormKind::SlowReaders, 4), "storm slow-readers 4/s");
    EXPECT_EQ(storm_phase_name(StormKind::HalfOpen, 10), "storm half-open 10/s");
}

TEST(StormLadder, RatesAloneAreFc03AndAKindNamesItsStorm) {
    EXPECT_EQ(*parse_rates("100,500,1000"), (std::vector<double>{100, 500, 1000}));
    EXPECT_FALSE(parse_rates("500,100"));
    EXPECT_FALSE(parse_rates("100,x"));
    EXPECT_FALSE(parse_rates(""));
    auto ladder = parse_ladder("100,1000");
    ASSERT_TRUE(ladder);
    EXPECT_EQ(ladder->kind, StormKind::Fc03);
    ladder = parse_ladder("half-open:5,50");
    ASSERT_TRUE(ladder);
    EXPECT_EQ(ladder->kind, StormKind::HalfOpen);
    EXPECT_EQ(ladder->rates, (std::vector<double>{5, 50}));
    EXPECT_EQ(parse_ladder("slow-readers:1,4")->kind, StormKind::SlowReaders);
    EXPECT_EQ(parse_ladder("opens:10")->kind, StormKind::Opens);
    EXPECT_EQ(parse_ladder("floods:10").error(),
              "--ladder 'floods:10': 'floods' is no storm (opens, slow-readers, half-open, fc01, "
              "fc02, fc03, fc04, fc05, fc06, fc07, fc08, fc0b, fc0c, fc0f, fc10, fc11, fc14, "
              "fc15, fc16, fc17, fc18, fc2b, or requests: every request storm)");
    EXPECT_EQ(parse_ladder("opens:10,5").error(),
              "--ladder 'opens:10,5': give rising rates per second, e.g. 100,500,1000");
}

}  // namespace
}  // namespace mblab::robustness
