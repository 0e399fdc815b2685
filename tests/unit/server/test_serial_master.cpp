// The master's side of a serial line [SER 2.4.1] on a manual clock: a request, the frames that
// come back, and what the master makes of them.
#include <gtest/gtest.h>

#include <chrono>

#include "support/hex.hpp"
#include "support/manual_clock.hpp"
#include "transport/serial_master.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using transport::SerialMaster;
using State = SerialMaster::State;
using Timeout = SerialMaster::Timeout;
using Verdict = SerialMaster::Verdict;

constexpr auto kT35 = 1750us;

struct MasterTrace {
    ManualClock clock;
    SerialMaster master{{.inter_frame = kT35, .turnaround = 100ms, .response_timeout = 500ms}};

    Verdict hears(std::uint8_t unit, std::string_view pdu) {
        return master.on_frame(unit, hex(pdu), clock.now());
    }
    Timeout after(std::chrono::microseconds by) {
        clock.advance(by);
        return master.on_time(clock.now());
    }
};

TEST(SerialMaster, AnswerEndsTheExchange) {
    MasterTrace t;
    t.master.request_sent(1, 0x03, t.clock.now());
    EXPECT_EQ(t.master.state(), State::WaitingReply);
    EXPECT_EQ(t.master.deadline(), t.clock.now() + 500ms);
    EXPECT_EQ(t.after(20ms), Timeout::None);
    EXPECT_EQ(t.hears(1, "03 02 00 07"), Verdict::Answer);
    EXPECT_EQ(t.master.state(), State::Idle);
    // The next request waits for t3.5 of silence after the answer [SER 2.5.1.1].
    EXPECT_EQ(t.master.line_free_at(), t.clock.now() + kT35);
    EXPECT_EQ(t.after(1s), Timeout::None);
}

TEST(SerialMaster, ExceptionAnswersItsRequest) {
    MasterTrace t;
    t.master.request_sent(1, 0x03, t.clock.now());
    EXPECT_EQ(t.hears(1, "83 02"), Verdict::Answer);
}

TEST(SerialMaster, NoAnswerWithinTheResponseTimeout) {
    MasterTrace t;
    t.master.request_sent(1, 0x03, t.clock.now());
    EXPECT_EQ(t.after(499ms), Timeout::None);
    EXPECT_EQ(t.after(1ms), Timeout::NoAnswer);
    EXPECT_EQ(t.master.state(), State::Idle);
    // The answer that comes now is late: its request is over.
    t.clock.advance(5ms);
    EXPECT_EQ(t.hears(1, "03 02 00 07"), Verdict::Unasked);
}

TEST(SerialMaster, AnswerFromAnotherAddressKeepsTheTimerRunning) {
    MasterTrace t;
    const auto sent = t.clock.now();
    t.master.request_sent(1, 0x03, sent);
    EXPECT_EQ(t.after(100ms), Timeout::None);
    EXPECT_EQ(t.hears(2, "03 02 00 07"), Verdict::OtherAddress);
    EXPECT_EQ(t.master.state(), State::WaitingReply);
    EXPECT_EQ(t.master.deadline(), sent + 500ms);
    EXPECT_EQ(t.hears(1, "06 00 01 00 2A"), Verdict::OtherFunction);
    EXPECT_EQ(t.master.deadline(), sent + 500ms);
    // Its own answer still ends the exchange before the deadline...
    EXPECT_EQ(t.hears(1, "03 02 00 07"), Verdict::Answer);

    // ... and without one the timeout comes when it would have.
    MasterTrace u;
    u.master.request_sent(1, 0x03, u.clock.now());
    EXPECT_EQ(u.after(100ms), Timeout::None);
    EXPECT_EQ(u.hears(2, "03 02 00 07"), Verdict::OtherAddress);
    EXPECT_EQ(u.after(399ms), Timeout::None);
    EXPECT_EQ(u.after(1ms), Timeout::NoAnswer);
}

TEST(SerialMaster, BroadcastWaitsTheTurnaroundAndNoAnswer) {
    MasterTrace t;
    const auto sent = t.clock.now();
    t.master.request_sent(0, 0x06, sent);
    EXPECT_EQ(t.master.state(), State::Turnaround);
    EXPECT_EQ(t.master.line_free_at(), sent + 100ms);
    EXPECT_EQ(t.hears(1, "06 00 01 00 2A"), Verdict::Unasked);
    EXPECT_EQ(t.after(99ms), Timeout::None);
    EXPECT_EQ(t.after(1ms), Timeout::TurnaroundOver);
    EXPECT_EQ(t.master.state(), State::Idle);
}

TEST(SerialMaster, NoiseKeepsTheLineBusy) {
    MasterTrace t;
    t.master.heard(t.clock.now());
    EXPECT_EQ(t.master.line_free_at(), t.clock.now() + kT35);
    EXPECT_EQ(t.hears(7, "03 02 00 07"), Verdict::Unasked);
}

}  // namespace
}  // namespace mblab::test
