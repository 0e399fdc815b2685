// Server mechanics over real sockets, against a scripted device: framing, pipelining, limits,
// timers and the device's fault replies.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

#include "blocking_client.hpp"
#include "child_process.hpp"
#include "scripted_handler.hpp"
#include "server/tcp_server.hpp"
#include "server_fixture.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

class ServerSession : public ServerFixture {
  protected:
    void start(server::ServerOptions options = {}) { start_server(handler_, std::move(options)); }
    ScriptedHandler handler_;
};

TEST_F(ServerSession, AnswersOneRequest) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(client.transact("12 34 00 00 00 06 01 03 00 00 00 01"),
              "12 34 00 00 00 06 01 03 00 00 00 01");
}

// Bad input 1: a protocol id other than 0 is dropped unanswered; the next frame is served.
TEST_F(ServerSession, DiscardsProtocolIdNotZeroAndStaysInStep) {
    start();
    auto client = connect();
    ASSERT_TRUE(
        client.send_hex("00 07 00 01 00 06 01 03 00 00 00 01"
                        "00 08 00 00 00 06 01 03 00 00 00 02"));
    EXPECT_EQ(client.read_adu(), "00 08 00 00 00 06 01 03 00 00 00 02");
    EXPECT_EQ(handler_.calls.load(), 1);
}

// An overlong length field, CTP 9.1.3: length 0xFF with a 6-byte body is answered 03 after the
// wait.
TEST_F(ServerSession, AnswersImproperLengthWithException03ThenStaysInStep) {
    start();
    auto client = connect();
    EXPECT_EQ(client.transact("00 00 00 00 00 FF 01 03 00 00 00 01"), "00 00 00 00 00 03 01 83 03");
    EXPECT_EQ(client.transact("00 02 00 00 00 06 01 03 00 00 00 01"),
              "00 02 00 00 00 06 01 03 00 00 00 01");
    EXPECT_EQ(handler_.calls.load(), 1);
}

// Issue 17 item 8: a request sent with, or soon after, a frame of length 0xFF was taken for that
// frame's body and lost without answer or close.
TEST_F(ServerSession, RequestInTheSameWriteAsALength0xFFFrameIsAnsweredAfterIts03) {
    start();
    auto client = connect();
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 FF 01 03 00 00 00 01"
                        "00 02 00 00 00 06 01 03 00 00 00 01"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 83 03");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 06 01 03 00 00 00 01");
    EXPECT_EQ(client.transact("00 03 00 00 00 03 01 08 00"), "00 03 00 00 00 03 01 08 00");
}

TEST_F(ServerSession, RequestsSentDuringTheWaitOfALength0xFFFrameAreAnsweredInOrder) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 01 00 00 00 FF 01 03 00 00 00 01"));
    ASSERT_TRUE(client.send_hex("00 02 00 00 00 03 01 08 00"));
    ASSERT_TRUE(client.send_hex("00 03 00 00 00 03 01 08 01"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 83 03");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 01 08 00");
    EXPECT_EQ(client.read_adu(), "00 03 00 00 00 03 01 08 01");
}

TEST_F(ServerSession, RequestAfterALength0xFFFrameIsAnsweredWhenTheClientHalfCloses) {
    start();
    auto client = connect();
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 FF 01 03 00 00 00 01"
                        "00 02 00 00 00 03 01 08 00"));
    client.shutdown_send();
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 83 03");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer());
}

TEST_F(ServerSession, AnswersShortBodyWithException03ThenStaysInStep) {
    start();
    auto client = connect();
    EXPECT_EQ(client.transact("00 05 00 00 00 0A 11 10 00 01"), "00 05 00 00 00 03 11 90 03");
    EXPECT_EQ(client.transact("00 06 00 00 00 03 11 08 00"), "00 06 00 00 00 03 11 08 00");
}

TEST_F(ServerSession, DropsUnfinishedHeaderWithoutAnswer) {
    server::ServerOptions options;
    options.partial_frame_timeout = 50ms;
    start(options);
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 05 00 00"));
    std::this_thread::sleep_for(200ms);  // past the partial-frame wait: the 4 bytes are dropped
    EXPECT_EQ(client.transact("00 06 00 00 00 03 11 08 00"), "00 06 00 00 00 03 11 08 00");
}

// Bad input 3: a body longer than any PDU closes the connection.
TEST_F(ServerSession, ClosesOnOversizeFrame) {
    start();
    auto client = connect();
    std::vector<std::uint8_t> frame = hex("00 01 00 00 01 05 01 10");
    frame.resize(7 + 0x105 - 1, 0x00);
    ASSERT_TRUE(client.send(frame));
    EXPECT_TRUE(client.closed_by_peer());
}

TEST_F(ServerSession, ClosesOnOverlongBodyAfterLength0xFF) {
    start();
    auto client = connect();
    std::vector<std::uint8_t> frame = hex("00 01 00 00 00 FF 01 10");
    frame.resize(7 + 254, 0x00);
    ASSERT_TRUE(client.send(frame));
    EXPECT_TRUE(client.closed_by_peer());
}

TEST_F(ServerSession, AnswersEarlierRequestsThenClosesOnLengthZero) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 01 00 00 00 03 01 08 00  00 02 00 00 00 00 01"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer());
}

// A request and the FIN right behind it, as `nc -N` sends them: when both came before the
// server read, its one read took the request and the end stayed unread; a third of such
// connections then waited for the idle timeout (here none) instead of closing.
TEST_F(ServerSession, ClosesAfterAnsweringARequestWhoseFinCameWithIt) {
    server::ServerOptions options;
    options.idle_timeout = std::chrono::milliseconds(0);
    start(options);
    for (int i = 0; i < 60; ++i) {
        auto client = connect();
        ASSERT_TRUE(client.send_hex("00 01 00 00 00 03 01 08 00"));
        client.shutdown_send();
        ASSERT_EQ(client.read_adu(), "00 01 00 00 00 03 01 08 00") << "connection " << i;
        ASSERT_TRUE(client.closed_by_peer(std::chrono::seconds(5))) << "connection " << i;
    }
}

// Bad input 10: several requests in one segment, one split over segments, byte at a time.
TEST_F(ServerSession, AnswersSeveralRequestsInOneSegmentInOrder) {
    start();
    auto client = connect();
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 06 01 03 00 00 00 01"
                        "00 02 00 00 00 06 01 04 00 00 00 02"
                        "00 03 00 00 00 03 01 08 00"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 06 01 03 00 00 00 01");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 06 01 04 00 00 00 02");
    EXPECT_EQ(client.read_adu(), "00 03 00 00 00 03 01 08 00");
}

TEST_F(ServerSession, AnswersRequestSplitOverSegments) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 09 00 00 00"));
    std::this_thread::sleep_for(20ms);
    ASSERT_TRUE(client.send_hex("06 01 03 00"));
    std::this_thread::sleep_for(20ms);
    ASSERT_TRUE(client.send_hex("00 00 01 00 0A 00 00 00 03 01 08 00"));
    EXPECT_EQ(client.read_adu(), "00 09 00 00 00 06 01 03 00 00 00 01");
    EXPECT_EQ(client.read_adu(), "00 0A 00 00 00 03 01 08 00");
}

TEST_F(ServerSession, AnswersRequestSentByteAtATime) {
    start();
    auto client = connect();
    for (auto byte : hex("00 0B 00 00 00 06 01 03 00 10 00 02")) {
        ASSERT_TRUE(client.send(std::span(&byte, 1)));
        std::this_thread::sleep_for(2ms);
    }
    EXPECT_EQ(client.read_adu(), "00 0B 00 00 00 06 01 03 00 10 00 02");
}

// Bad input 10: more outstanding requests than the server takes are answered 06 (busy).
TEST_F(ServerSession, AnswersBusyPastMaxOutstanding) {
    server::ServerOptions options;
    options.max_outstanding = 2;
    start(options);
    auto client = connect();
    // Each asks for a 500 ms delay, so the first two are still outstanding when 3 and 4 come.
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 03 01 41 32  00 02 00 00 00 03 01 41 32"
                        "00 03 00 00 00 03 01 41 32  00 04 00 00 00 03 01 41 32"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 41 32");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 01 41 32");
    EXPECT_EQ(client.read_adu(), "00 03 00 00 00 03 01 C1 06");
    EXPECT_EQ(client.read_adu(), "00 04 00 00 00 03 01 C1 06");
    EXPECT_EQ(handler_.calls.load(), 2);
    EXPECT_EQ(server::ServerStats::read(stats().busy), 2U);
}

TEST_F(ServerSession, PipelinedRequestsWithoutDelayAreNeverBusy) {
    server::ServerOptions options;
    options.max_outstanding = 2;
    start(options);
    auto client = connect();
    std::string batch;
    for (int i = 0; i < 100; ++i) {
        batch += to_hex(std::vector<std::uint8_t>{0, static_cast<std::uint8_t>(i)}) +
                 " 00 00 00 03 01 08 00 ";
    }
    ASSERT_TRUE(client.send_hex(batch));
    for (int i = 0; i < 100; ++i) {
        auto tid = to_hex(std::vector<std::uint8_t>{0, static_cast<std::uint8_t>(i)});
        ASSERT_EQ(client.read_adu(), tid + " 00 00 00 03 01 08 00");
    }
}

// A fault delay holds back its answer and those behind it, and no other connection.
TEST_F(ServerSession, DelayedAnswerKeepsOrderAndDoesNotBlockOthers) {
    start();
    auto slow = connect();
    auto other = connect();
    ASSERT_TRUE(slow.send_hex("00 01 00 00 00 03 01 41 FF  00 02 00 00 00 03 01 08 00"));
    EXPECT_EQ(other.transact("00 03 00 00 00 03 01 08 00"), "00 03 00 00 00 03 01 08 00");
    EXPECT_TRUE(slow.read(1, 0ms).empty());  // held back 2.55 s
    EXPECT_EQ(slow.read_adu(), "00 01 00 00 00 03 01 41 FF");
    EXPECT_EQ(slow.read_adu(), "00 02 00 00 00 03 01 08 00");
}

TEST_F(ServerSession, DropFaultSendsNothing) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 01 00 00 00 02 01 42  00 02 00 00 00 03 01 08 00"));
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 01 08 00");
}

TEST_F(ServerSession, CloseFaultAnswersEarlierRequestsThenCloses) {
    start();
    auto client = connect();
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 03 01 08 00  00 02 00 00 00 02 01 43"
                        "00 03 00 00 00 03 01 08 00"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer());
    EXPECT_EQ(handler_.calls.load(), 2);
}

TEST_F(ServerSession, GarbageFaultIsFramedAsTheAnswer) {
    start();
    auto client = connect();
    EXPECT_EQ(client.transact("00 01 00 00 00 02 07 44"), "00 01 00 00 00 05 07 DE AD BE EF");
}

// Bad input 11: unit ids 0 and 0xFF reach the device and come back in the answer.
TEST_F(ServerSession, PassesUnitIdsThrough) {
    start();
    auto client = connect();
    EXPECT_EQ(client.transact("00 01 00 00 00 03 00 08 00"), "00 01 00 00 00 03 00 08 00");
    EXPECT_EQ(handler_.last_unit.load(), 0);
    EXPECT_EQ(client.transact("00 02 00 00 00 03 FF 08 00"), "00 02 00 00 00 03 FF 08 00");
    EXPECT_EQ(handler_.last_unit.load(), 0xFF);
}

TEST_F(ServerSession, AnswersRequestsSentBeforeTheClientHalfCloses) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 01 00 00 00 03 01 08 00"));
    client.shutdown_send();
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer());
}

// Bad input 12: a full server closes its oldest idle connection to admit a new one.
TEST_F(ServerSession, FullServerClosesOldestIdleConnection) {
    server::ServerOptions options;
    options.max_connections = 2;
    start(options);
    auto oldest = connect();
    EXPECT_EQ(oldest.transact("00 01 00 00 00 03 01 08 00"), "00 01 00 00 00 03 01 08 00");
    auto newer = connect();
    EXPECT_EQ(newer.transact("00 02 00 00 00 03 01 08 00"), "00 02 00 00 00 03 01 08 00");
    auto newest = connect();
    EXPECT_EQ(newest.transact("00 03 00 00 00 03 01 08 00"), "00 03 00 00 00 03 01 08 00");
    EXPECT_TRUE(oldest.closed_by_peer());
    EXPECT_EQ(newer.transact("00 04 00 00 00 03 01 08 00"), "00 04 00 00 00 03 01 08 00");
    EXPECT_EQ(server_->listener_counters().evicted_idle.load(), 1U);
}

TEST_F(ServerSession, FullServerWithNoIdleConnectionRefusesNewcomer) {
    server::ServerOptions options;
    options.max_connections = 1;
    start(options);
    auto busy = connect();
    ASSERT_TRUE(busy.send_hex("00 01 00 00 00 03 01 41 64"));  // answer held back 1 s
    std::this_thread::sleep_for(100ms);                        // so the server has read it
    auto refused = connect();
    EXPECT_TRUE(refused.closed_by_peer());
    EXPECT_EQ(busy.read_adu(), "00 01 00 00 00 03 01 41 64");
    EXPECT_EQ(server_->listener_counters().refused_full.load(), 1U);
}

// A device whose function 0x45 holds the server's thread for 300 ms and then answers 1 s later,
// so a test can line up events for the server to find all at once when it looks again.
class StallingHandler : public ScriptedHandler {
  public:
    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        if (request.front() != 0x45) return ScriptedHandler::handle(context, request, response);
        std::this_thread::sleep_for(300ms);  // the slow device itself, not a synchronisation
        device::Reply reply;
        reply.size = std::min(request.size(), response.size());
        std::copy_n(request.begin(), reply.size, response.begin());
        reply.delay = 1s;
        return reply;
    }
};

// Issue 17 item 9: a client that closes and one that connects at once, seen together by a full
// server: the closed session, not yet destroyed, still counted and the newcomer was refused.
TEST_F(ServerSession, ClosedConnectionFreesItsPlaceAtOnce) {
    StallingHandler handler;
    server::ServerOptions options;
    options.max_connections = 2;
    start_server(handler, options);
    auto busy = connect();  // holds the other place, owed an answer throughout
    for (int i = 0; i < 3; ++i) {
        auto leaving = connect();
        ASSERT_EQ(leaving.transact("00 01 00 00 00 03 01 08 00"), "00 01 00 00 00 03 01 08 00");
        ASSERT_TRUE(busy.send_hex("00 02 00 00 00 02 01 45"));
        // While the server is held: the close and the newcomer's connect wait for it together.
        leaving = BlockingClient();
        auto newcomer = connect();
        EXPECT_EQ(newcomer.transact("00 03 00 00 00 03 01 08 00"), "00 03 00 00 00 03 01 08 00")
            << "round " << i;
        EXPECT_EQ(busy.read_adu(), "00 02 00 00 00 02 01 45");
    }
    EXPECT_EQ(server_->listener_counters().refused_full.load(), 0U);
}

// Bad input 13: a client not on the allow-list is refused.
TEST_F(ServerSession, RefusesClientNotOnAllowList) {
    server::ServerOptions options;
    std::string error;
    ASSERT_TRUE(options.allow.add("10.0.0.0/8", error)) << error;
    start(options);
    auto client = connect();
    client.send_hex("00 01 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer());
    EXPECT_EQ(handler_.calls.load(), 0);
    EXPECT_EQ(server_->listener_counters().refused_address.load(), 1U);
}

TEST_F(ServerSession, ServesClientOnAllowList) {
    server::ServerOptions options;
    std::string error;
    ASSERT_TRUE(options.allow.add("10.0.0.0/8", error)) << error;
    ASSERT_TRUE(options.allow.add("127.0.0.1", error)) << error;
    start(options);
    auto client = connect();
    EXPECT_EQ(client.transact("00 01 00 00 00 03 01 08 00"), "00 01 00 00 00 03 01 08 00");
}

// Bad input 14: a slowloris client (part of a header, then silence) is closed by the idle
// timer, and so is one that drips a byte now and then; others are served meanwhile.
TEST_F(ServerSession, IdleTimerClosesSlowlorisWhileOthersAreServed) {
    server::ServerOptions options;
    options.idle_timeout = 300ms;
    options.partial_frame_timeout = 1s;
    start(options);
    auto silent = connect();
    ASSERT_TRUE(silent.send_hex("00 01 00"));
    auto dripping = connect();
    auto served = connect();
    bool dripping_closed = false;
    for (int i = 0; i < 100 && !dripping_closed; ++i) {
        auto tid = to_hex(std::vector<std::uint8_t>{0, static_cast<std::uint8_t>(i)});
        ASSERT_EQ(served.transact(tid + " 00 00 00 03 01 08 00"), tid + " 00 00 00 03 01 08 00");
        // A header announcing 253 bytes, then the body a byte at a time: never a whole frame.
        std::uint8_t byte = i < 7 ? hex("00 01 00 00 00 FE 01")[static_cast<std::size_t>(i)] : 0x10;
        dripping_closed = !dripping.send(std::span(&byte, 1)) || dripping.closed_by_peer(50ms);
    }
    EXPECT_TRUE(dripping_closed);
    EXPECT_TRUE(silent.closed_by_peer());
    EXPECT_GE(server::ServerStats::read(stats().closed_idle), 2U);
}

TEST_F(ServerSession, StopClosesConnections) {
    start();
    auto client = connect();
    EXPECT_EQ(client.transact("00 01 00 00 00 03 01 08 00"), "00 01 00 00 00 03 01 08 00");
    server_->stop();
    EXPECT_TRUE(client.closed_by_peer());
}

TEST_F(ServerSession, SecondServerOnTheSamePortFailsWithOneLine) {
    start();
    ScriptedHandler other_handler;
    server::BackgroundServer other(other_handler);
    auto result = other.start({asio::ip::address_v4::loopback(), port_});
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error(),
              "cannot listen on 127.0.0.1:" + std::to_string(port_) + ": Address already in use");
}

// A program the process starts while it serves (the tests run the mblab binary beside an
// in-process server) holds none of the server's sockets: neither the listener nor a connection.
TEST_F(ServerSession, ChildProcessesInheritNoServerSocket) {
    start();
    auto client = connect();
    ASSERT_TRUE(client.connected());
    ASSERT_EQ(client.transact("00 01 00 00 00 06 01 03 00 00 00 01"),
              "00 01 00 00 00 06 01 03 00 00 00 01");  // the connection is accepted
    ChildProcess child({"/bin/sh", "-c", "ls -l /proc/self/fd/ | grep -c socket: || true"});
    const auto sockets = child.read_stdout_line(5s);
    ASSERT_TRUE(sockets.has_value());
    EXPECT_EQ(*sockets, "0");
    EXPECT_EQ(child.wait_exit(5s), 0);
}

}  // namespace
}  // namespace mblab::test
