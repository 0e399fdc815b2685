// The server's real driver (MbapDriver, as TcpSession runs it) with Modbus/TCP Security over a
// memory pair: the trace's client speaks TLS, the hex is the plaintext inside it.
#include <gtest/gtest.h>

#include <memory>

#include "mbap_session_trace.hpp"
#include "support/hex.hpp"
#include "support/lab_tls.hpp"

namespace mblab::test {
namespace {

using server::ServerStats;

TraceTls operator_may_read() {
    return {lab_server_context(), lab_client_context("client-Operator"),
            std::make_shared<const device::RoleRules>(
                std::vector{device::RoleRule{"Operator", {3}, {}, {}, {}, {}}})};
}

TEST(MbapDriverTls, AnswersInsideTlsUnderTheCertificatesRole) {
    SessionTrace t(operator_may_read());
    EXPECT_EQ(ServerStats::read(t.stats().tls_handshakes), 1U);
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 01 06 00 08 12 34");
    t.device_answers(
        "00 01 00 00 00 05 01 03 02 00 07"
        "00 02 00 00 00 03 01 86 01");  // FC 06 is not the Operator's here
    EXPECT_EQ(ServerStats::read(t.stats().denied), 1U);
    EXPECT_FALSE(t.closed());
}

TEST(MbapDriverTls, AnswersReadyInOnePassGoOutAsOneRecord) {
    SessionTrace t(operator_may_read());
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");  // the tickets went out with it
    const auto before = t.server_end().written();
    t.client_sends(
        "00 02 00 00 00 06 01 03 00 07 00 01"
        "00 03 00 00 00 06 01 03 00 08 00 01"
        "00 04 00 00 00 06 01 03 00 09 00 01");
    // Three answers of 11 bytes in one TLS 1.3 record: header 5, type 1, tag 16.
    EXPECT_EQ(t.server_end().written() - before, 3U * 11U + 5U + 1U + 16U);
    t.device_answers(
        "00 02 00 00 00 05 01 03 02 00 07"
        "00 03 00 00 00 05 01 03 02 00 08"
        "00 04 00 00 00 05 01 03 02 00 09");
}

// TLS record buffers (about 33 KB) go back after the handshake and after a quiet second; the
// next request takes them again and is answered as ever.
TEST(MbapDriverTls, AQuietSessionRestsItsTlsBuffers) {
    SessionTrace t(operator_may_read());
    const auto& server = t.server_tls()->session();
    EXPECT_TRUE(server.resting()) << "after the handshake";
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    EXPECT_FALSE(server.resting());
    t.after(std::chrono::milliseconds(999));
    EXPECT_FALSE(server.resting());
    t.after(std::chrono::milliseconds(1));
    EXPECT_TRUE(server.resting());
    t.client_sends("00 02 00 00 00 06 01 03 00 08 00 01");
    t.device_answers("00 02 00 00 00 05 01 03 02 00 08");
    EXPECT_FALSE(server.resting());
    EXPECT_FALSE(t.closed());
}

// An answer the client does not take keeps its record in the buffers: no rest until it is out.
TEST(MbapDriverTls, AnAnswerWaitingForRoomKeepsTheBuffers) {
    SessionTrace t(operator_may_read());
    t.server_end().set_window(10);
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.after(std::chrono::milliseconds(2'500));
    EXPECT_FALSE(t.server_tls()->session().resting());
    EXPECT_FALSE(t.closed());
    t.server_end().set_window(64 * 1024);
    t.run();
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    t.after(std::chrono::milliseconds(1'000));
    EXPECT_TRUE(t.server_tls()->session().resting());
}

// The session rested while the device took its time; the delayed answer's record took the
// buffers again, and they go back a quiet second after it.
TEST(MbapDriverTls, ADelayedAnswerRestsAgainAfterIt) {
    auto tls = operator_may_read();
    tls.roles = std::make_shared<const device::RoleRules>(
        std::vector{device::RoleRule{"Operator", {3, 0x41}, {}, {}, {}, {}}});
    SessionTrace t(tls);
    const auto& server = t.server_tls()->session();
    t.client_sends("00 01 00 00 00 03 01 41 96");  // answered after 1.5 s
    t.after(std::chrono::milliseconds(1'200));
    EXPECT_TRUE(server.resting()) << "quiet for a second, the answer not yet due";
    t.after(std::chrono::milliseconds(300));
    t.device_answers("00 01 00 00 00 03 01 41 96");
    EXPECT_FALSE(server.resting());
    t.after(std::chrono::milliseconds(1'000));
    EXPECT_TRUE(server.resting());
}

TEST(MbapDriverTls, ShortWritesOnTheServersSideLoseNothing) {
    SessionTrace t(operator_may_read());
    t.server_end().set_max_write(5);
    t.client_sends(
        "00 01 00 00 00 06 01 03 00 07 00 01"
        "00 02 00 00 00 06 01 03 00 08 00 02");
    EXPECT_EQ(t.client_reads_everything(),
              "00 01 00 00 00 05 01 03 02 00 07 "
              "00 02 00 00 00 07 01 03 04 00 08 00 09");
}

TEST(MbapDriverTls, BarePduIsRefusedWithCloseNotify) {
    SessionTrace t(operator_may_read());
    t.client_sends("03 00 00 00 02");
    EXPECT_TRUE(t.closed());
    ASSERT_EQ(t.refusals().size(), 1U);
    EXPECT_NE(t.refusals()[0].find("bare PDU"), std::string::npos) << t.refusals()[0];
    EXPECT_EQ(ServerStats::read(t.stats().tls_refused), 1U);
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
    EXPECT_EQ(t.client_tls()->session().state(), security::TlsChannel::State::Closed);
}

// The refusal ends as any session does: close_notify and the FIN, then the session reads and
// drops what the client still sends until it ends, since bytes that met a closed socket would
// reset the connection under the close_notify still on its way.
TEST(MbapDriverTls, BarePduRefusalLingersUntilTheClientEnds) {
    SessionTrace t(operator_may_read());
    t.client_sends("03 00 00 00 02");
    t.client_sends("03 00 00 00 03");
    EXPECT_FALSE(t.released());
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
    EXPECT_EQ(t.client_tls()->session().state(), security::TlsChannel::State::Closed);
    EXPECT_FALSE(t.client().is_reset());
    t.client_shuts_down();
    EXPECT_TRUE(t.released());
}

TEST(MbapDriverTls, HandshakeNotFinishedInTheLimitIsRefused) {
    auto tls = operator_may_read();
    tls.handshake = false;
    SessionTrace t(tls);
    EXPECT_FALSE(t.closed());
    t.after(std::chrono::milliseconds(9'999));
    EXPECT_FALSE(t.closed());
    t.after(std::chrono::milliseconds(1));
    EXPECT_TRUE(t.closed());
    ASSERT_EQ(t.refusals().size(), 1U);
    EXPECT_EQ(t.refusals()[0], "the TLS handshake did not finish within the handshake limit");
}

TEST(MbapDriverTls, ClientWithoutTheServersTrustIsRefusedInTheHandshake) {
    // The server's certificate does not name example.org: the client refuses it, and the
    // server reads the alert as a refused handshake.
    auto tls = operator_may_read();
    tls.client = nullptr;  // the client is this test's own
    SessionTrace t(tls);
    transport::TlsStream other(t.client(), lab_client_context("client-Operator"),
                               transport::TlsStream::Side::Client, "example.org");
    other.start();
    for (int i = 0; i < 20 && other.handshaking(); ++i) {
        t.run();
        other.handshake();
    }
    t.run();
    EXPECT_NE(other.error().find("hostname mismatch"), std::string::npos) << other.error();
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(ServerStats::read(t.stats().tls_refused), 1U);
}

TEST(MbapDriverTls, CloseNotifyEndsTheSessionAfterItsAnswers) {
    SessionTrace t(operator_may_read());
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.client_shuts_down();
    EXPECT_TRUE(t.closed());
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
}

// The last request and the close_notify in one read: the answer goes out, then the server's
// close_notify, and the session ends (it used to wait for the idle timeout, reading nothing).
TEST(MbapDriverTls, ARequestAndCloseNotifyReadTogetherAreAnsweredThenClosed) {
    SessionTrace t(operator_may_read());
    t.client_sends("00 01 00 00 00 06 01 03 00 07 00 01");
    t.device_answers("00 01 00 00 00 05 01 03 02 00 07");
    const auto request = hex("00 02 00 00 00 06 01 03 00 08 00 01");
    ASSERT_EQ(t.client_channel().write(request).bytes, request.size());
    t.client_channel().shutdown_write();
    t.run();
    EXPECT_TRUE(t.closed());
    t.device_answers("00 02 00 00 00 05 01 03 02 00 08");
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
}

// TLS 1.3 closes each direction on its own (RFC 8446 6.1): an answer still owed when the client's
// close_notify comes (here a serial line's, through the gateway) goes out before the server's.
TEST(MbapDriverTls, OverTls13AnAnswerOwedAtCloseNotifyIsSentBeforeTheServersCloseNotify) {
    SessionTrace t(operator_may_read());
    t.client_sends("00 01 00 00 00 06 09 03 00 07 00 01");
    ASSERT_EQ(t.device().waiting_on_line(), 1U);
    t.client_shuts_down();
    EXPECT_FALSE(t.closed()) << "an answer is owed";
    t.device().line_answers();
    t.device_answers("00 01 00 00 00 05 09 03 02 00 07");
    EXPECT_TRUE(t.closed());
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
    EXPECT_EQ(t.client_tls()->session().state(), security::TlsChannel::State::Closed);
}

// The Operator's session, its client offering TLS 1.2 only.
TraceTls operator_over_tls12() {
    auto tls = operator_may_read();
    auto client = security::make_client_context(lab_files("client-Operator"),
                                                {security::ClientVersions::Tls12, true});
    EXPECT_TRUE(client) << client.error();
    if (client) tls.client = *client;
    return tls;
}

// TLS 1.2 answers close_notify at once and discards what is pending (RFC 5246 7.2.1).
TEST(MbapDriverTls, OverTls12CloseNotifyIsAnsweredAtOnceAndTheOwedAnswerDropped) {
    SessionTrace t(operator_over_tls12());
    ASSERT_EQ(t.client_tls()->session().peer().version, "TLSv1.2");
    t.client_sends("00 01 00 00 00 06 09 03 00 07 00 01");
    ASSERT_EQ(t.device().waiting_on_line(), 1U);
    t.client_shuts_down();
    EXPECT_TRUE(t.closed());
    t.device().line_answers();
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(t.client_channel().read(buffer).status, transport::Io::Status::EndOfInput);
}

// The close_notify that answers the client's waits for room like any record, and the FIN goes
// behind it whole: cut, the client's TLS would read a truncation instead of the end.
TEST(MbapDriverTls, OverTls12TheAnsweringCloseNotifyGoesOutWholeBeforeTheFin) {
    SessionTrace t(operator_over_tls12());
    EXPECT_EQ(t.client_reads(), "");
    t.server_end().set_window(10);  // a third of the close_notify's record
    t.client_shuts_down();
    EXPECT_FALSE(t.released());
    std::array<std::uint8_t, 16> buffer{};
    auto io = t.client_channel().read(buffer);
    for (int i = 0; i < 8 && io.status == transport::Io::Status::WouldBlock; ++i) {
        t.run();
        io = t.client_channel().read(buffer);
    }
    EXPECT_EQ(io.status, transport::Io::Status::EndOfInput);
    EXPECT_EQ(t.client_tls()->session().state(), security::TlsChannel::State::Closed);
    t.run();
    EXPECT_TRUE(t.released());
}

}  // namespace
}  // namespace mblab::test
