// Which connection a full table gives up for a newcomer: one whose session is over and that only
// waits for the client's end first, then one still in its TLS handshake (the oldest of them), then
// the oldest stalled, then the oldest that never carried a request, then the oldest idle; a busy
// one never.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "transport/connection_table.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;
using transport::Clock;
using transport::Standing;

class FakeConnection final : public transport::TrackedConnection {
  public:
    FakeConnection(transport::ConnectionTable& table, Standing standing, Clock::time_point last)
        : table_(table), standing_(standing), last_(last) {
        table_.add(*this);
    }
    Standing standing(Clock::time_point) const override { return standing_; }
    Clock::time_point last_activity() const override { return last_; }
    void close() override {
        closed = true;
        table_.remove(*this);
    }
    bool closed = false;

  private:
    transport::ConnectionTable& table_;
    Standing standing_;
    Clock::time_point last_;
};

// The attack: an authenticated session, idle between polls and the oldest, and newer connections
// that never finish their handshakes. Each newcomer took the session's place.
TEST(ConnectionTable, AHandshakeInProgressGoesBeforeAnEstablishedSession) {
    const auto t0 = Clock::time_point{} + 1h;
    transport::ConnectionTable table;
    FakeConnection session(table, Standing::Idle, t0);
    FakeConnection stalled(table, Standing::Stalled, t0 + 1s);
    FakeConnection newer(table, Standing::Handshaking, t0 + 3s);
    FakeConnection older(table, Standing::Handshaking, t0 + 2s);
    FakeConnection busy(table, Standing::Busy, t0);
    FakeConnection ending(table, Standing::Ending, t0 + 3s);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Ending);
    EXPECT_TRUE(ending.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Handshaking);
    EXPECT_TRUE(older.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Handshaking);
    EXPECT_TRUE(newer.closed);
    // None handshaking: the policy of [TCPG] 4.2.1.1 as before.
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Stalled);
    EXPECT_TRUE(stalled.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Idle);
    EXPECT_TRUE(session.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 4s), Standing::Busy);
    EXPECT_FALSE(busy.closed);
    EXPECT_EQ(table.size(), 1U);
}

// Connections opened faster than a client polls: each is newer than the client's last request
// when the next one comes, so by age alone the client went; one that never carried a request
// goes first whatever its age.
TEST(ConnectionTable, AConnectionThatNeverCarriedARequestGoesBeforeOneInUse) {
    const auto t0 = Clock::time_point{} + 1h;
    transport::ConnectionTable table;
    FakeConnection polled(table, Standing::Idle, t0);
    FakeConnection newer_unused(table, Standing::Unused, t0 + 2s);
    FakeConnection older_unused(table, Standing::Unused, t0 + 1s);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 3s), Standing::Unused);
    EXPECT_TRUE(older_unused.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 3s), Standing::Unused);
    EXPECT_TRUE(newer_unused.closed);
    EXPECT_FALSE(polled.closed);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 3s), Standing::Idle);
    EXPECT_TRUE(polled.closed);
    // A stalled one still goes before an unused one.
    FakeConnection unused(table, Standing::Unused, t0);
    FakeConnection stalled(table, Standing::Stalled, t0 + 2s);
    EXPECT_EQ(table.close_one_for_newcomer(t0 + 3s), Standing::Stalled);
    EXPECT_FALSE(unused.closed);
}

}  // namespace
}  // namespace mblab::test
