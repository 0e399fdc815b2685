// The serial server's protocol as traces, without a port or a pty: what the master sends, how
// time passes on the line, what the device answers and when. LineTrace drives LineSessionCore as
// LineSession does; PacedLine delivers bytes at a line's character time.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "server/line_session_core.hpp"
#include "support/hex.hpp"
#include "support/manual_clock.hpp"
#include "support/paced_line.hpp"
#include "transport/serial_port.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using server::LineCarrier;
using server::LineClock;
using server::LineError;
using server::ServerStats;

std::uint64_t count(const ServerStats::Counter& counter) {
    return ServerStats::read(counter);
}

// A device on the line at address 1: FC 03 reads register N as N; FC 08 echoes; FC 41 NN
// echoes after NN * 10 ms; FC 43 asks to close. A broadcast (0) is executed, never answered,
// and other addresses are not its own, so it stays silent, as ReferenceDevice does.
class LineDevice final : public device::RequestHandler {
  public:
    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        ++requests;
        if (context.unit == 0) ++broadcasts;
        if (context.unit != 1) return {device::ReplyAction::NoAnswer, 0, {}};
        device::Reply reply;
        if (request[0] == 0x43) return {device::ReplyAction::Close, 0, {}};
        if (request[0] == 0x03 && request.size() == 5) {
            const unsigned first = request[1] << 8 | request[2];
            const unsigned quantity = request[3] << 8 | request[4];
            response[0] = 0x03;
            response[1] = static_cast<std::uint8_t>(quantity * 2);
            for (unsigned i = 0; i < quantity; ++i) {
                response[2 + 2 * i] = static_cast<std::uint8_t>((first + i) >> 8);
                response[3 + 2 * i] = static_cast<std::uint8_t>(first + i);
            }
            return {device::ReplyAction::Answer, 2 + 2 * quantity, {}};
        }
        if (request[0] == 0x41 && request.size() > 1) reply.delay = request[1] * 10ms;
        std::memcpy(response.data(), request.data(), request.size());
        reply.size = request.size();
        return reply;
    }

    int requests = 0;
    int broadcasts = 0;
};

struct Answer {
    std::string bytes;
    LineClock::time_point at;
};

// The core, its device and a manual clock; bytes come all at once (a USB packet, a TCP segment)
// or paced by a PacedLine.
class LineTrace {
  public:
    explicit LineTrace(server::LineSetup setup, LineCarrier carrier = LineCarrier::SerialPort,
                       server::LineLimits limits = {}, unsigned baud = 19200)
        : line(baud), core_(device, with_hooks(std::move(setup)), carrier, limits, stats, now()) {}

    LineClock::time_point now() const { return clock_.now(); }
    // Bytes that arrive now, in one read.
    void master_sends(std::string_view text) {
        core_.receive(hex(text), now());
        run();
    }
    // Bytes that the master starts sending now on the paced line.
    void master_paces(std::string_view text) { line.send(hex(text), now()); }
    // Moves the clock by `by`, waking the core at its deadlines and handing it the paced bytes
    // as they arrive, one at a time as a UART gives them.
    void after(LineClock::duration by) {
        const auto until = now() + by;
        for (;;) {
            // While an answer is owed the port's buffer holds what arrives.
            const auto arrival =
                core_.wants_input() ? line.next_arrival() : LineClock::time_point::max();
            const auto next = std::min(core_.deadline(), arrival);
            if (next > until) break;
            clock_.advance_to(next);
            run();
        }
        clock_.advance_to(until);
        run();
    }
    // The answers written since the last call, each with when it went out.
    std::vector<Answer> answers() { return std::exchange(answers_, {}); }
    // The answers to `text` sent now, a second later: past any turnaround and silence.
    std::vector<Answer> answers_to(std::string_view text) {
        master_sends(text);
        after(1s);
        return answers();
    }
    bool ending() const { return core_.ending(); }

    LineDevice device;
    ServerStats stats;
    PacedLine line;
    std::vector<LineError> line_errors;

  private:
    server::LineSetup with_hooks(server::LineSetup setup) {
        setup.hooks.on_frame_error = [this](LineError error) { line_errors.push_back(error); };
        return setup;
    }
    void run() {
        for (bool moved = true; moved && !core_.ending();) {
            moved = false;
            if (core_.wants_input()) {
                // Bytes that came while an answer was owed waited in the port's buffer.
                for (const auto& arrival : line.take(now())) {
                    const std::uint8_t byte = arrival.byte;
                    core_.receive({&byte, 1}, std::max(arrival.at, held_since_));
                }
            }
            core_.on_time(now());
            if (const auto out = core_.output(now()); !out.empty()) {
                answers_.push_back({to_hex(out), now()});
                core_.sent(now());
                held_since_ = now();
                moved = true;
            }
        }
    }

    ManualClock clock_;
    server::LineSessionCore core_;
    std::vector<Answer> answers_;
    LineClock::time_point held_since_{};
};

server::LineSetup rtu_line(unsigned baud = 19200, bool strict = false) {
    transport::SerialUrl url;
    url.line.baud = baud;
    url.strict_timing = strict;
    return server::serial_line_setup(url, {});
}

const auto kT35At19200 = transport::rtu_char_times(19200).t35;

TEST(LineSessionCore, AnswersARequestOnceTheTurnaroundIsOver) {
    LineTrace t(rtu_line());
    const auto sent = t.now();
    t.master_sends("01 03 00 07 00 01 35 CB");
    EXPECT_TRUE(t.answers().empty());
    t.after(kT35At19200 - 1us);
    EXPECT_TRUE(t.answers().empty());
    t.after(1us);
    const auto answers = t.answers();
    ASSERT_EQ(answers.size(), 1U);
    EXPECT_EQ(answers[0].bytes, "01 03 02 00 07 F9 86");
    EXPECT_EQ(answers[0].at, sent + kT35At19200);
    EXPECT_EQ(count(t.stats.requests), 1U);
}

TEST(LineSessionCore, RequestToAnotherAddressGoesUnanswered) {
    LineTrace t(rtu_line());
    EXPECT_TRUE(t.answers_to("02 03 00 07 00 01 35 F8").empty());
    // The device is asked, as every device on the line reads every frame, and keeps silent.
    EXPECT_EQ(t.device.requests, 1);
    // The next request to its own address is answered as usual.
    ASSERT_EQ(t.answers_to("01 03 00 07 00 01 35 CB").size(), 1U);
}

TEST(LineSessionCore, BroadcastIsExecutedAndNotAnswered) {
    LineTrace t(rtu_line());
    EXPECT_TRUE(t.answers_to("00 06 00 01 00 2A 58 04").empty());
    EXPECT_EQ(t.device.broadcasts, 1);
}

TEST(LineSessionCore, BadCrcIsDroppedAndCounted) {
    LineTrace t(rtu_line());
    EXPECT_TRUE(t.answers_to("01 03 00 07 00 01 35 CC").empty());
    EXPECT_EQ(t.device.requests, 0);
    EXPECT_EQ(count(t.stats.frames_dropped), 1U);
    EXPECT_EQ(t.line_errors, std::vector<LineError>{LineError::Checksum});
}

TEST(LineSessionCore, DelayedAnswerWaitsForItsDelay) {
    LineTrace t(rtu_line());
    const auto sent = t.now();
    t.master_sends("01 41 05 D0 53");  // unknown layout: t3.5 of silence ends it
    t.after(50ms);
    EXPECT_TRUE(t.answers().empty());
    t.after(kT35At19200);
    const auto answers = t.answers();
    ASSERT_EQ(answers.size(), 1U);
    EXPECT_EQ(answers[0].bytes, "01 41 05 D0 53");
    EXPECT_EQ(answers[0].at, sent + kT35At19200 + 50ms);
}

TEST(LineSessionCore, TcpClientIdlesOutButASerialLineNever) {
    auto setup = rtu_line();
    setup.idle_timeout = 5s;
    LineTrace tcp(setup, LineCarrier::Tcp);
    tcp.after(4999ms);
    EXPECT_FALSE(tcp.ending());
    tcp.after(1ms);
    EXPECT_TRUE(tcp.ending());
    EXPECT_EQ(count(tcp.stats.closed_idle), 1U);

    LineTrace line(rtu_line());
    line.after(24h);
    EXPECT_FALSE(line.ending());
}

TEST(LineSessionCore, FrameTrickledOverTcpPastTheFrameLimitCloses) {
    auto setup = rtu_line();
    setup.timing.silence = 250ms;  // RTU over TCP: how long a frame may wait for its bytes
    LineTrace t(setup, LineCarrier::Tcp, {.partial_frame_timeout = 250ms, .frame_limit = 1s});
    for (const char* byte : {"01", "03", "00", "07", "00"}) {
        t.master_sends(byte);
        t.after(200ms);
    }
    EXPECT_TRUE(t.ending());
    EXPECT_EQ(count(t.stats.closed_slow_frame), 1U);
}

TEST(LineSessionCore, TwoRequestsInOneReadAreAnsweredInTurn) {
    LineTrace t(rtu_line());
    const auto answers = t.answers_to("01 03 00 07 00 01 35 CB  01 03 00 08 00 02 45 C9");
    ASSERT_EQ(answers.size(), 2U);
    EXPECT_EQ(answers[0].bytes, "01 03 02 00 07 F9 86");
    EXPECT_EQ(answers[1].bytes, "01 03 04 00 08 00 09 BB F7");
}

TEST(LineSessionCore, CloseFaultEndsATcpConnectionNotALine) {
    auto setup = rtu_line();
    setup.unknown_length = protocol::RtuFramer::UnknownLength::EndOnCrcMatch;
    LineTrace tcp(setup, LineCarrier::Tcp);
    tcp.master_sends("01 43 41 D1");
    EXPECT_TRUE(tcp.ending());

    LineTrace line(rtu_line());
    line.master_sends("01 43 41 D1");
    line.after(1s);
    EXPECT_FALSE(line.ending());
    EXPECT_EQ(line.device.requests, 1);
}

// [SER 2.5.1.1]: t3.5 of silence ends a frame. FC 08 sub-function 00 has no length in its
// layout: only the silence after its last character ends it.
TEST(LineSessionCore, PacedFrameEndsAtT35AfterItsLastCharacter) {
    LineTrace t(rtu_line());
    t.master_paces("01 08 00 00 12 34 ED 7C");
    const auto last = t.line.last_arrival();
    EXPECT_EQ(last - t.now(), 8 * t.line.char_time());
    t.after(last - t.now() + kT35At19200 - 1us);
    EXPECT_EQ(t.device.requests, 0);
    t.after(1us);
    EXPECT_EQ(t.device.requests, 1);
    const auto answers = t.answers();
    ASSERT_EQ(answers.size(), 1U);
    EXPECT_EQ(answers[0].bytes, "01 08 00 00 12 34 ED 7C");
    EXPECT_EQ(answers[0].at, last + kT35At19200);
}

// [SER 2.5.1.1]: a silence over t1.5 between two characters spoils the frame (strict=1).
TEST(LineSessionCore, PacedFrameBrokenByAGapOverT15IsDropped) {
    LineTrace t(rtu_line(19200, true));
    t.line.gap_before(4, 1ms);  // t1.5 at 19200 baud is 859 us
    t.master_paces("01 03 00 07 00 01 35 CB");
    t.after(1s);
    EXPECT_TRUE(t.answers().empty());
    EXPECT_EQ(t.device.requests, 0);
    EXPECT_EQ(count(t.stats.frames_dropped), 1U);
    EXPECT_EQ(t.line_errors, std::vector<LineError>{LineError::ShortFrame});

    // The same frame with a short pause in it is answered.
    t.line.gap_before(12, 200us);
    t.master_paces("01 03 00 07 00 01 35 CB");
    t.after(1s);
    ASSERT_EQ(t.answers().size(), 1U);
    EXPECT_EQ(t.device.requests, 1);
}

}  // namespace
}  // namespace mblab::test
