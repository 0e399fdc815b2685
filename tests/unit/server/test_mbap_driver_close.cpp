// How the server's driver lets a connection go after the session ended it with its answers:
// its output ends at once, then it reads and drops what the client still sends until the
// client ends too (or the linger time passes), because a socket closed with input unread is
// reset (RFC 1122 4.2.2.13) and a reset loses the answers the client has not read yet.
#include <gtest/gtest.h>

#include <array>
#include <memory>

#include "mbap_session_trace.hpp"
#include "support/hex.hpp"
#include "support/lab_tls.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

// Unit 1's FC 43 closes the connection (the trace device's fault "close").
constexpr const char* kAnsweredThenClose =
    "00 01 00 00 00 06 01 03 00 07 00 01"
    "00 02 00 00 00 02 01 43"
    "00 03 00 00 00 06 01 03 00 08 00 01";

// The client's first request answered, its second closed by the device, its third dropped: the
// session lingers from then on.
void answer_then_close(SessionTrace& t) {
    t.client_sends(kAnsweredThenClose);
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    ASSERT_TRUE(t.lingering());
}

// The Operator's session over TLS 1.3, allowed FC 03 and the closing FC 43.
TraceTls operator_over_tls() {
    return TraceTls{lab_server_context(), lab_client_context("client-Operator"),
                    std::make_shared<const device::RoleRules>(
                        std::vector{device::RoleRule{"Operator", {0x03, 0x43}, {}, {}, {}, {}}})};
}

// The client reads the end of the session. A FIN alone would also read as the end; its TLS
// session closed means a whole close_notify came first.
void expect_close_notify_then_fin(SessionTrace& t) {
    std::array<std::uint8_t, 16> buffer{};
    const auto end = t.client_channel().read(buffer);
    EXPECT_EQ(end.status, transport::Io::Status::EndOfInput) << t.client_channel().error();
    EXPECT_EQ(t.client_tls()->session().state(), security::TlsChannel::State::Closed);
}

// The client ends too: the server lets go, with nothing left unread to reset the connection.
void client_ends_and_is_let_go(SessionTrace& t) {
    t.client().shutdown_write();
    t.run();
    EXPECT_TRUE(t.released());
    EXPECT_FALSE(t.client().is_reset());
}

// The memory pair resets as a socket does when closed with input unread: without the lingering
// the client's request 4, sent while the answer waited, would reset the connection and lose it.
TEST(MbapDriverClose, AfterItsAnswersTheSessionReadsWhatTheClientStillSendsUntilItEnds) {
    SessionTrace t;
    t.server_end().set_window(4);  // the answer waits for the client to read it
    t.client_sends(kAnsweredThenClose);
    EXPECT_FALSE(t.closed()) << "the answer is still on its way";
    t.server_end().set_window(4096);
    t.client_sends("00 04 00 00 00 06 01 03 00 09 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_TRUE(t.client_sees_end_of_input());
    EXPECT_TRUE(t.lingering());
    t.client_sends("00 05 00 00 00 06 01 03 00 0A 00 01");
    t.device_says_nothing();
    EXPECT_FALSE(t.released());
    t.client_shuts_down();
    EXPECT_TRUE(t.released());
    EXPECT_FALSE(t.client().is_reset());
}

TEST(MbapDriverClose, ASessionLetsGoOfAClientThatNeverEndsAtTheLingerLimit) {
    SessionTrace t;
    answer_then_close(t);
    t.after(1999ms);
    EXPECT_TRUE(t.lingering());
    t.after(1ms);
    EXPECT_TRUE(t.released());
}

// A flood while lingering is read in bounded pieces: one readiness takes a piece and says more
// may remain, and the readiness loop comes back for the rest.
TEST(MbapDriverClose, AFloodWhileLingeringIsDroppedInPieces) {
    SessionTrace t;
    answer_then_close(t);
    std::string flood;
    for (int i = 0; i < 20'000; ++i)
        flood += "00 06 00 00 00 06 01 03 00 0B 00 01";
    const auto bytes = hex(flood);
    ASSERT_EQ(t.client_channel().write(bytes).bytes, bytes.size());
    t.driver().readable(t.clock().now());
    EXPECT_GT(t.server_end().pending(), 0U);
    EXPECT_TRUE(t.driver().input_may_remain());
    t.run();
    EXPECT_EQ(t.server_end().pending(), 0U);
    t.device_says_nothing();
    EXPECT_TRUE(t.lingering());
}

// Each piece the client sends gives it 2 s more, up to 30 s in all: bytes sent after the close
// would meet a closed socket and reset the answers the client has not read yet.
TEST(MbapDriverClose, AClientStillSendingKeepsTheSessionReadingUpToThirtySeconds) {
    SessionTrace t;
    answer_then_close(t);
    for (int i = 0; i < 19; ++i) {
        t.after(1500ms);
        ASSERT_TRUE(t.lingering()) << "at " << t.clock().elapsed();
        t.client_sends("00 07 00 00 00 06 01 03 00 0C 00 01");
    }
    t.after(1500ms);
    EXPECT_TRUE(t.released());
}

TEST(MbapDriverClose, AClientThatResetsWhileTheSessionLingersIsLetGo) {
    SessionTrace t;
    answer_then_close(t);
    t.client_resets();
    EXPECT_TRUE(t.released());
}

// Over TLS the session's end is close_notify and the FIN; what follows is dropped as it comes,
// below TLS: records, the client's close_notify, then its FIN.
TEST(MbapDriverClose, OverTlsTheClientsLaterRecordsAreDroppedUntilItsFin) {
    SessionTrace t(operator_over_tls());
    t.client_sends(kAnsweredThenClose);
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
    ASSERT_TRUE(t.lingering());
    t.run();  // the client's close_notify, which answered the server's
    EXPECT_TRUE(t.lingering());
    client_ends_and_is_let_go(t);
}

// The close_notify waits for room as the answers do, and the FIN goes behind it: a FIN inside
// its record would be a truncation, which the client's TLS reports as an attack on the session.
TEST(MbapDriverClose, OverTlsACloseNotifyThatFindsTheSocketFullGoesOutWholeBeforeTheFin) {
    SessionTrace t(operator_over_tls());
    // Room for the answer's record (33 bytes in TLS 1.3), not for the close_notify's 24 after it.
    EXPECT_EQ(t.client_reads(), "");  // the session tickets
    t.server_end().set_window(40);
    t.client_sends(kAnsweredThenClose);
    ASSERT_TRUE(t.lingering());
    EXPECT_TRUE(t.driver().wants_write());
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    expect_close_notify_then_fin(t);
    EXPECT_FALSE(t.driver().wants_write());
    client_ends_and_is_let_go(t);
}

// The same when the client closes first (TLS 1.3): the answer it is owed, then the close_notify
// that answers its own, whole, then the FIN.
TEST(MbapDriverClose, OverTlsTheCloseNotifyAnsweringTheClientsWaitsForRoomToo) {
    SessionTrace t(operator_over_tls());
    EXPECT_EQ(t.client_reads(), "");  // the session tickets
    t.server_end().set_window(40);
    const auto request = hex("00 01 00 00 00 06 01 03 00 07 00 01");
    ASSERT_EQ(t.client_channel().write(request).bytes, request.size());
    t.client_tls()->close_notify();
    t.run();
    EXPECT_FALSE(t.released());
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    expect_close_notify_then_fin(t);
    t.run();
    EXPECT_TRUE(t.released());
    EXPECT_FALSE(t.client().is_reset());
}

}  // namespace
}  // namespace mblab::test
