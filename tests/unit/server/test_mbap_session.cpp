// The Modbus/TCP session's protocol as traces, without sockets or sleeps: what the client sends,
// how much time passes, what the device answers. SessionTrace drives MbapSession as TcpSession
// does; TraceDevice (mbap_session_trace.hpp) says what each unit and function code does.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "mbap_session_trace.hpp"
#include "server/server_stats.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using server::ServerStats;
using transport::Standing;

std::uint64_t count(const ServerStats::Counter& counter) {
    return ServerStats::read(counter);
}

server::MbapSessionLimits idle_after(std::chrono::milliseconds timeout) {
    server::MbapSessionLimits limits;
    limits.idle_timeout = timeout;
    return limits;
}

TEST(MbapSessionTrace, AnswersARequest) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_EQ(count(t.stats().requests), 1U);
}

TEST(MbapSessionTrace, AnswersPipelinedRequestsInRequestOrder) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 01 06 00 08 12 34"
        "00 03 00 00 00 06 01 03 00 09 00 02");
    t.device_answers(
        "00 01 00 00 00 05 01 03 02 00 07"
        "00 02 00 00 00 06 01 06 00 08 12 34"
        "00 03 00 00 00 07 01 03 04 00 09 00 0A");
}

TEST(MbapSessionTrace, FrameSplitAcrossReadsIsAnsweredOnceWhole) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 06 01");
    t.device_says_nothing();
    t.after(100ms);
    t.client_sends("03 00 07 00 01  00 02 00 00");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    t.client_sends("00 06 01 03 00 08 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 08");
}

// Seed 000 9.1.3: a frame whose bytes stop coming is answered 03 once the gap runs out, and the
// stream carries on in step.
TEST(MbapSessionTrace, UnfinishedFrameIsAnswered03WhenItsBytesStopComing) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 06 01 03 00");
    t.after(249ms);
    t.device_says_nothing();
    t.after(1ms);
    t.device_answers("00 01 00 00 00 03 01 83 03");
    t.client_sends("00 02 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 07");
    EXPECT_EQ(count(t.stats().frames_dropped), 1U);
    // Told to the owner (for the traffic log) with as much of the request as came.
    EXPECT_EQ(t.own_answers(), std::vector<std::string>{"unit 1 from 192.0.2.9:50312: 03 -> 03"});
}

TEST(MbapSessionTrace, UnfinishedHeaderIsDroppedWithoutAnswer) {
    SessionTrace t;
    t.client_sends("00 01 00 00");
    t.after(250ms);
    t.device_says_nothing();
    t.client_sends("00 02 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 07");
}

TEST(MbapSessionTrace, FrameTimeoutBoundsTheGapBetweenBytesNotTheirNumber) {
    SessionTrace t;
    t.client_sends_byte_by_byte("00 01 00 00 00 06 01 03 00 07 00 01", 80ms);
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_FALSE(t.closed());
}

// Issue 17 item 1: a frame still arriving after the frame limit is answered 03 and closed, so a
// client that trickles a byte inside every gap cannot hold its place for ever.
TEST(MbapSessionTrace, FrameStillArrivingAtTheFrameLimitIsAnswered03AndClosed) {
    SessionTrace t;
    t.client_sends_byte_by_byte("00 01 00 00 00 06 01 03 00 00 00", 90ms);
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Stalled);
    t.after(99ms);
    t.device_says_nothing();
    t.after(1ms);
    t.device_answers("00 01 00 00 00 03 01 83 03");
    EXPECT_TRUE(t.closed());
    EXPECT_TRUE(t.client_sees_end_of_input());
    EXPECT_EQ(count(t.stats().closed_slow_frame), 1U);
}

TEST(MbapSessionTrace, IdleConnectionIsClosedAtTheIdleTimeout) {
    SessionTrace t(idle_after(1000ms));
    // Until a whole request comes the connection has not been used.
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Unused);
    t.client_sends("00 01 00 00 00 06 01");
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Busy);
    t.client_sends("03 00 07 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Idle);
    t.after(999ms);
    EXPECT_FALSE(t.closed());
    t.after(1ms);
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(count(t.stats().closed_idle), 1U);
}

TEST(MbapSessionTrace, ConnectionOwedADeferredAnswerIsNotIdle) {
    SessionTrace t(idle_after(1000ms));
    t.client_sends("00 01 00 00 00 06 09 03 00 07 00 01");
    t.after(5000ms);
    EXPECT_FALSE(t.closed());
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Busy);
    t.device().line_answers();
    t.device_answers("00 01 00 00 00 05 09 03 02 00 07");
    t.after(1000ms);
    EXPECT_TRUE(t.closed());
}

// A gateway's answer comes later, from the serial line: the answers behind it wait for it.
TEST(MbapSessionTrace, DeferredAnswerHoldsItsPlaceInOrder) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 06 09 03 00 07 00 01"
        "00 02 00 00 00 06 01 03 00 08 00 01");
    t.device_says_nothing();
    t.device().line_answers();
    t.device_answers(
        "00 01 00 00 00 05 09 03 02 00 07"
        "00 02 00 00 00 05 01 03 02 00 08");
}

TEST(MbapSessionTrace, DelayedAnswerHoldsBackTheAnswersBehindIt) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 03 01 41 05"
        "00 02 00 00 00 06 01 03 00 07 00 01");
    t.after(49ms);
    t.device_says_nothing();
    t.after(1ms);
    t.device_answers(
        "00 01 00 00 00 03 01 41 05"
        "00 02 00 00 00 05 01 03 02 00 07");
}

TEST(MbapSessionTrace, RequestsPastMaxOutstandingBehindADelayedAnswerAreBusy) {
    server::MbapSessionLimits limits;
    limits.max_outstanding = 2;
    SessionTrace t(limits);
    t.client_sends(
        "00 01 00 00 00 03 01 41 0A"
        "00 02 00 00 00 06 01 03 00 07 00 01"
        "00 03 00 00 00 06 01 03 00 08 00 01");
    t.device_says_nothing();
    t.after(100ms);
    t.device_answers(
        "00 01 00 00 00 03 01 41 0A"
        "00 02 00 00 00 05 01 03 02 00 07"
        "00 03 00 00 00 03 01 83 06");
    EXPECT_EQ(t.busy_replies(), 1);
    EXPECT_EQ(count(t.stats().busy), 1U);
    EXPECT_EQ(t.own_answers(),
              std::vector<std::string>{"unit 1 from 192.0.2.9:50312: 03 00 08 00 01 -> 06"});
}

std::string read_requests(int first, int last) {
    std::string out;
    char frame[64];
    for (int i = first; i <= last; ++i) {
        std::snprintf(frame, sizeof frame, "00 %02X 00 00 00 06 01 03 00 %02X 00 01 ", i, i);
        out += frame;
    }
    return out;
}

std::string read_answers(int first, int last) {
    std::string out;
    char frame[64];
    for (int i = first; i <= last; ++i) {
        std::snprintf(frame, sizeof frame, "00 %02X 00 00 00 05 01 03 02 00 %02X ", i, i);
        out += frame;
    }
    return to_hex(hex(out));
}

// A client that sends and does not read: the session answers until max_outstanding answers wait,
// then stops reading, so TCP flow control holds the client back; as the client takes answers,
// reading resumes. Nothing is answered busy: the answers are ready, only the client is slow.
TEST(MbapSessionTrace, StopsReadingWhileTheClientTakesNoAnswersAndResumesAsItDoes) {
    SessionTrace t;
    t.server_end().set_window(22);  // two answers in flight, then the client reads no more
    t.client_sends(read_requests(1, 40));
    EXPECT_FALSE(t.reading());
    EXPECT_EQ(t.session().answers_queued(), 16U);
    EXPECT_EQ(t.client_reads_everything(), read_answers(1, 40));
    EXPECT_TRUE(t.reading());
    EXPECT_EQ(count(t.stats().busy), 0U);
}

TEST(MbapSessionTrace, ClientThatLeavesItsAnswersUnreadCountsAsStalled) {
    SessionTrace t;
    t.server_end().set_window(0);
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Busy);
    t.after(250ms);
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Stalled);
    t.server_end().set_window(1000);
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_EQ(t.session().standing(t.clock().now()), Standing::Idle);
}

TEST(MbapSessionTrace, ShortWritesDeliverEveryAnswerWholeAndInOrder) {
    SessionTrace t;
    t.server_end().set_max_write(5);
    t.client_sends(read_requests(1, 3));
    EXPECT_EQ(t.client_reads_everything(), read_answers(1, 3));
}

// [TCPG 4.4.2.2]: a frame of another protocol is skipped whole; the stream stays in step.
TEST(MbapSessionTrace, ProtocolIdNotZeroIsSkippedAndTheStreamStaysInStep) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 01 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 01 03 00 08 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 08");
    EXPECT_EQ(count(t.stats().frames_dropped), 1U);
    EXPECT_EQ(count(t.stats().requests), 1U);
}

// Seed 000 9.1.3 and issue 17 item 8: length 0xFF with a 6-byte body is answered 03 once the
// wait runs out, and a request sent in the same write is found again after that body.
TEST(MbapSessionTrace, OverlongLengthIsAnswered03AndTheRequestsAfterItsBodyAreAnswered) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 FF 01 03 00 00 00 01"
        "00 02 00 00 00 06 01 03 00 08 00 01");
    t.after(249ms);
    t.device_says_nothing();
    t.client_sends("00 03 00 00 00 06 01 03 00 09 00 01");
    t.after(250ms);
    t.device_answers(
        "00 01 00 00 00 03 01 83 03"
        "00 02 00 00 00 05 01 03 02 00 08"
        "00 03 00 00 00 05 01 03 02 00 09");
    EXPECT_FALSE(t.closed());
}

TEST(MbapSessionTrace, OverlongBodyPastAPduClosesTheConnection) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 FF 01 10" + std::string(254 * 2, '0'));
    EXPECT_TRUE(t.closed());
    t.device_says_nothing();
    EXPECT_EQ(count(t.stats().closed_bad_frame), 1U);
}

TEST(MbapSessionTrace, LengthZeroAnswersTheEarlierRequestsThenCloses) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(count(t.stats().closed_bad_frame), 1U);
}

TEST(MbapSessionTrace, BroadcastIsNotAnsweredAndTheAnswersAroundItKeepTheirOrder) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 00 06 00 01 00 05"
        "00 03 00 00 00 06 01 03 00 08 00 01");
    t.device_answers(
        "00 01 00 00 00 05 01 03 02 00 07"
        "00 03 00 00 00 05 01 03 02 00 08");
    EXPECT_EQ(t.device().broadcasts, 1);
}

// A broadcast a gateway puts on its line is answered later with nothing: it holds its place, then
// lets the answers behind it go, without a write of zero bytes.
TEST(MbapSessionTrace, BroadcastThroughTheLineHoldsItsPlaceAndSendsNothing) {
    SessionTrace t;
    t.device().broadcasts_on_line = true;
    t.client_sends(
        "00 01 00 00 00 06 00 06 00 01 00 05"
        "00 02 00 00 00 06 01 03 00 08 00 01");
    t.device_says_nothing();
    t.device().line_answers();
    t.device_answers("00 02 00 00 00 05 01 03 02 00 08");
    t.client_sends("00 03 00 00 00 06 00 06 00 01 00 05");
    t.device().line_answers();
    t.device_says_nothing();
    EXPECT_EQ(t.session().answers_queued(), 0U);
    t.client_sends("00 04 00 00 00 06 01 03 00 09 00 01");
    t.device_answers("00 04 00 00 00 05 01 03 02 00 09");
}

TEST(MbapSessionTrace, DropFaultSendsNothingForItsRequest) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 02 01 42"
        "00 02 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 07");
}

TEST(MbapSessionTrace, CloseFaultAnswersTheEarlierRequestsThenCloses) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 02 01 43"
        "00 03 00 00 00 06 01 03 00 08 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(count(t.stats().requests), 2U);
}

TEST(MbapSessionTrace, RequestsSentBeforeTheClientHalfClosesAreAnsweredThenItCloses) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.client_sends("00 02 00 00 00 03 01 41 03");
    t.client_shuts_down();
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_FALSE(t.closed());
    t.after(30ms);
    t.device_answers("00 02 00 00 00 03 01 41 03");
    EXPECT_TRUE(t.released()) << "the client ended first: there is nothing to linger for";
    EXPECT_TRUE(t.client_sees_end_of_input());
}

TEST(MbapSessionTrace, EndOfInputAnswersTheUnfinishedFrameAtOnce) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 06 01 03 00");
    t.client_shuts_down();
    t.device_answers("00 01 00 00 00 03 01 83 03");
    EXPECT_TRUE(t.closed());
}

TEST(MbapSessionTrace, RequestAfterAnOverlongFrameIsAnsweredWhenTheClientHalfCloses) {
    SessionTrace t;
    t.client_sends(
        "00 01 00 00 00 FF 01 03 00 00 00 01"
        "00 02 00 00 00 06 01 03 00 08 00 01");
    t.client_shuts_down();
    t.device_answers(
        "00 01 00 00 00 03 01 83 03"
        "00 02 00 00 00 05 01 03 02 00 08");
    EXPECT_TRUE(t.closed());
}

TEST(MbapSessionTrace, ClientThatResetsEndsTheSession) {
    SessionTrace t;
    t.client_sends("00 01 00 00 00 03 01 41 05");
    t.client_resets();
    EXPECT_TRUE(t.closed());
}

}  // namespace
}  // namespace mblab::test

namespace mblab::test {
namespace {

// Modbus/TCP Security: once the TLS handshake named the client's role, a request that role may
// not make is answered 01 by the session, without reaching the device, and counted.
TEST(MbapSessionTrace, RequestTheRoleMayNotMakeIsAnswered01) {
    SessionTrace t;
    const device::RoleRules rules({device::RoleRule{"ReadOnly", {3}, {}, {}, {}, {}}});
    t.session().authorize(rules, std::string("ReadOnly"));
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 01 06 00 08 12 34");
    t.device_answers(
        "00 01 00 00 00 05 01 03 02 00 07"
        "00 02 00 00 00 03 01 86 01");
    EXPECT_EQ(ServerStats::read(t.stats().denied), 1U);
    EXPECT_EQ(t.own_answers(),
              std::vector<std::string>{"unit 1 from 192.0.2.9:50312: 06 00 08 12 34 -> 01"});
}

TEST(MbapSessionTrace, ClientWithoutRoleIsRefusedEverything) {
    SessionTrace t;
    const device::RoleRules rules({device::RoleRule{"Administrator", {}, {}, {}, {}, {}}});
    t.session().authorize(rules, std::nullopt);
    t.client_sends("00 09 00 00 00 06 11 03 00 07 00 01");
    t.device_answers("00 09 00 00 00 03 11 83 01");
}

}  // namespace
}  // namespace mblab::test
