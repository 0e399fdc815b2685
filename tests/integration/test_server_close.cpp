// How the server ends a connection it closes after its answers while the client is still
// sending: it reads on until the client ends, since closing with input unread makes the kernel
// reset the connection (RFC 1122 4.2.2.13), and a reset throws away the answers not yet
// delivered.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "blocking_client.hpp"
#include "protocol/adu_writer.hpp"
#include "scripted_handler.hpp"
#include "server_fixture.hpp"

namespace mblab::test {
namespace {

void append_request(std::vector<std::uint8_t>& out, std::uint16_t transaction,
                    const std::vector<std::uint8_t>& pdu) {
    const auto at = out.size();
    out.resize(at + protocol::limits::kMbapHeader + pdu.size());
    protocol::write_mbap_adu({transaction, 0, 0, 1}, pdu, std::span(out).subspan(at));
}

class ServerClose : public ServerFixture {
  protected:
    ScriptedHandler handler_;
};

// A client with a small window pipelines 100 requests with 260-byte answers, then one the device
// answers by closing, then more. The answers wait in the server's socket for the window; before
// the fix the close reset the connection and the client read 15 of them, then ECONNRESET.
TEST_F(ServerClose, AnswersWaitingForTheClientsWindowArriveBeforeAnOrderlyEnd) {
    start_server(handler_, {});
    auto client = connect(4096);
    ASSERT_TRUE(client.connected());
    constexpr int kAnswered = 100;
    std::vector<std::uint8_t> bytes;
    for (int i = 0; i < kAnswered; ++i)
        append_request(bytes, static_cast<std::uint16_t>(i), std::vector<std::uint8_t>(253, 0x03));
    append_request(bytes, 1000, {ScriptedHandler::kClose});
    // Past what the server reads at once, so some stays in its socket when it stops reading.
    for (int i = 0; i < 1400; ++i)
        append_request(bytes, 2000, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(client.send(bytes));
    std::this_thread::sleep_for(300ms);  // the server has answered, closed and sent its end

    int answers = 0;
    while (client.read_adu(2s).size() > 0)
        ++answers;
    EXPECT_EQ(answers, kAnswered);
    EXPECT_EQ(client.end_error(), 0) << std::strerror(client.end_error());
}

// A client that reads the server's end but never sends its own: the server lets go after the
// linger time, so a client cannot hold a place in the connection table with a connection that
// is over.
TEST_F(ServerClose, ServerLetsGoOfAClientThatNeverEnds) {
    start_server(handler_, {});
    auto client = connect();
    ASSERT_TRUE(client.send_hex("00 01 00 00 00 03 01 08 00  00 02 00 00 00 02 01 43"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 01 08 00");
    EXPECT_TRUE(client.closed_by_peer(1s));
    EXPECT_EQ(client.end_error(), 0);
    const auto until = std::chrono::steady_clock::now() + 10s;
    while (stats().connections_open.load() != 0 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(50ms);
    EXPECT_EQ(stats().connections_open.load(), 0U);
}

// A full table gives up the connection whose session is over before a session still open,
// even one that is idle and older.
TEST_F(ServerClose, AFullTableGivesUpALingeringConnectionFirst) {
    server::ServerOptions options;
    options.max_connections = 2;
    start_server(handler_, options);
    auto idle = connect();
    EXPECT_EQ(idle.transact("00 01 00 00 00 03 01 08 00"), "00 01 00 00 00 03 01 08 00");
    auto ending = connect();
    ASSERT_TRUE(ending.send_hex("00 02 00 00 00 02 01 43"));
    EXPECT_TRUE(ending.closed_by_peer(1s));
    auto newcomer = connect();
    EXPECT_EQ(newcomer.transact("00 03 00 00 00 03 01 08 00"), "00 03 00 00 00 03 01 08 00");
    EXPECT_EQ(idle.transact("00 04 00 00 00 03 01 08 00"), "00 04 00 00 00 03 01 08 00");
}

}  // namespace
}  // namespace mblab::test
