// The load generator's connection in memory, on a manual clock: the test is the device, reading
// the requests off one end of a transport::MemoryPair and writing answers (hex in, hex out), and
// it reports readiness by calling on_event itself, as the worker's epoll loop would.
#include <gtest/gtest.h>
#include <sys/epoll.h>

#include <cerrno>
#include <chrono>
#include <limits>
#include <memory>
#include <vector>

#include "load/connection.hpp"
#include "load/connection_port.hpp"
#include "load/mix.hpp"
#include "load/plan.hpp"
#include "support/hex.hpp"
#include "support/manual_clock.hpp"
#include "transport/memory_channel.hpp"

namespace mblab::load {
namespace {

using namespace std::chrono_literals;
using test::hex;
using Bytes = std::vector<std::uint8_t>;

// A channel the connection may own that forwards to an end the test's pair keeps.
class EndChannel final : public transport::Channel {
  public:
    explicit EndChannel(transport::MemoryPair::End& end) : end_(end) {}
    // As a socket's descriptor, closed when the channel is dropped.
    ~EndChannel() override { end_.close(); }
    transport::Io read(std::span<std::uint8_t> out) override { return end_.read(out); }
    transport::Io writev(std::span<const iovec> buffers) override { return end_.writev(buffers); }
    bool input_may_remain() const override { return end_.input_may_remain(); }
    void shutdown_write() override { end_.shutdown_write(); }
    void close() override { end_.close(); }
    transport::PeerIdentity peer() const override { return end_.peer(); }
    const std::string& error() const override { return end_.error(); }

  private:
    transport::MemoryPair::End& end_;
};

// Every dial makes a new pair (a new connection), unless the test refuses it.
class MemoryPorts final : public ConnectionPorts {
  public:
    std::vector<std::unique_ptr<transport::MemoryPair>> pairs;
    int refuse = 0;  // errno the next dial fails with; 0: it connects
    std::size_t window = std::numeric_limits<std::size_t>::max();  // of the connection's end
    bool want_write = false;

    transport::MemoryPair::End& device() { return pairs.back()->server(); }

    std::unique_ptr<ConnectionPort> make(const LoadTarget&, void*) override {
        return std::make_unique<Port>(*this);
    }

  private:
    class Port final : public ConnectionPort {
      public:
        explicit Port(MemoryPorts& ports) : ports_(ports) {}
        Dial dial(int& error) override {
            if (ports_.refuse != 0) {
                error = ports_.refuse;
                return Dial::Failed;
            }
            ports_.pairs.push_back(std::make_unique<transport::MemoryPair>());
            ports_.pairs.back()->client().set_window(ports_.window);
            connected_ = true;
            return Dial::Open;
        }
        int dial_result() override { return 0; }
        std::unique_ptr<transport::Channel> take_channel() override {
            return std::make_unique<EndChannel>(ports_.pairs.back()->client());
        }
        void watch(bool want_write) override { ports_.want_write = want_write; }
        void release() override { connected_ = false; }
        bool connected() const override { return connected_; }

      private:
        MemoryPorts& ports_;
        bool connected_ = false;
    };
};

// One node, the generator's connection only, requests from `mix`.
LoadPlan plan_for(const char* mix, std::size_t pipeline) {
    LoadPlan plan;
    plan.targets.push_back({});
    plan.settings.pipeline = pipeline;
    plan.settings.timeout = 100ms;
    plan.settings.tests = false;
    conformance::Dut dut;
    dut.unit = 1;
    auto entries = parse_mix(mix);
    EXPECT_TRUE(entries.ok()) << entries.error();
    add_mix(plan, entries.value(), dut);
    return plan;
}

struct Rig {
    explicit Rig(const char* mix, std::size_t pipeline = 1)
        : plan(plan_for(mix, pipeline)),
          context{plan, ports, clock.now(), {}, true},
          tally(plan.exchanges.size(), plan.cases.size()),
          connection(context, tally, 0, LoadConnection::Role::Traffic, 7) {}

    // Connects and returns the requests the connection sent at once.
    Bytes start() {
        connection.start(clock.now());
        return requests();
    }
    // What the device has been sent since the last call.
    Bytes requests() {
        Bytes out(4096);
        const auto io = ports.device().read(out);
        out.resize(io.status == transport::Io::Status::Done ? io.bytes : 0);
        return out;
    }
    std::uint64_t failures(FailureKind kind) const {
        return tally.failures[static_cast<std::size_t>(kind)].get();
    }
    void answer(const Bytes& bytes) {
        ASSERT_EQ(ports.device().write(bytes).bytes, bytes.size());
        connection.on_event(EPOLLIN, clock.now());
    }

    test::ManualClock clock;
    MemoryPorts ports;
    LoadPlan plan;
    WorkerContext context;
    NodeTally tally;
    LoadConnection connection;
};

// The transaction id of the request at `at` in `bytes`.
Bytes tid(const Bytes& bytes, std::size_t at = 0) {
    return {bytes[at], bytes[at + 1]};
}

Bytes answer_to(const Bytes& id, const char* rest) {
    Bytes out = id;
    const Bytes tail = hex(rest);
    out.insert(out.end(), tail.begin(), tail.end());
    return out;
}

TEST(LoadConnection, KeepsItsWindowFullAndMatchesAnswersByTransactionId) {
    Rig rig("fc3:2", 2);
    const Bytes sent = rig.start();
    ASSERT_EQ(sent.size(), 24U);
    EXPECT_EQ(Bytes(sent.begin() + 2, sent.begin() + 12), hex("00 00 00 06 01 03 00 00 00 02"));
    EXPECT_EQ(Bytes(sent.begin() + 14, sent.end()), hex("00 00 00 06 01 03 00 00 00 02"));
    EXPECT_NE(tid(sent, 0), tid(sent, 12));
    EXPECT_EQ(rig.tally.sent.get(), 2U);

    // The second answer first: each finds its own request, and each frees a place in the window.
    rig.clock.advance(3ms);
    rig.answer(answer_to(tid(sent, 12), "00 00 00 07 01 03 04 00 2A 00 2B"));
    rig.answer(answer_to(tid(sent, 0), "00 00 00 07 01 03 04 00 2A 00 2B"));
    EXPECT_EQ(rig.tally.answered.get(), 2U);
    EXPECT_EQ(rig.tally.failure_total(), 0U);
    LatencySnapshot latency;
    rig.tally.latency.snapshot_into(latency);
    EXPECT_EQ(latency.count(), 2U);
    EXPECT_EQ(latency.max(), 3000U);        // microseconds, on the manual clock
    EXPECT_EQ(rig.requests().size(), 24U);  // two more went out
    EXPECT_EQ(rig.tally.sent.get(), 4U);
}

TEST(LoadConnection, AnAnswerSplitAcrossReadsIsJudgedOnceWhole) {
    Rig rig("fc3:1");
    const Bytes sent = rig.start();
    const Bytes whole = answer_to(tid(sent), "00 00 00 05 01 03 02 12 34");
    rig.answer(Bytes(whole.begin(), whole.begin() + 5));
    EXPECT_EQ(rig.tally.answered.get(), 0U);
    rig.answer(Bytes(whole.begin() + 5, whole.end()));
    EXPECT_EQ(rig.tally.answered.get(), 1U);
    EXPECT_EQ(rig.tally.failure_total(), 0U);
}

TEST(LoadConnection, ATimedOutRequestCountsOnceAndItsLateAnswerIsNotCountedAgain) {
    Rig rig("fc3:1");
    const Bytes first = rig.start();
    rig.clock.advance(99ms);
    rig.connection.tick(rig.clock.now());
    EXPECT_EQ(rig.failures(FailureKind::Timeout), 0U);
    rig.clock.advance(2ms);
    rig.connection.tick(rig.clock.now());
    EXPECT_EQ(rig.failures(FailureKind::Timeout), 1U);
    ASSERT_TRUE(rig.tally.first_failure);
    EXPECT_EQ(rig.tally.first_failure->kind, FailureKind::Timeout);
    EXPECT_EQ(rig.tally.first_failure->exchange, "fc3:1");

    // The window moved on to a new request with a new id; the old one's answer is late.
    const Bytes second = rig.requests();
    ASSERT_EQ(second.size(), 12U);
    EXPECT_NE(tid(second), tid(first));
    rig.answer(answer_to(tid(first), "00 00 00 05 01 03 02 00 01"));
    EXPECT_EQ(rig.tally.late.get(), 1U);
    EXPECT_EQ(rig.tally.answered.get(), 0U);
    EXPECT_EQ(rig.tally.failure_total(), 1U);
    rig.answer(answer_to(tid(second), "00 00 00 05 01 03 02 00 01"));
    EXPECT_EQ(rig.tally.answered.get(), 1U);
}

TEST(LoadConnection, AnExceptionWhereDataWasDueIsAFailureWithItsBytes) {
    Rig rig("fc3:1");
    const Bytes sent = rig.start();
    const Bytes exception = answer_to(tid(sent), "00 00 00 03 01 83 02");
    rig.answer(exception);
    EXPECT_EQ(rig.failures(FailureKind::UnexpectedException), 1U);
    ASSERT_TRUE(rig.tally.first_failure);
    EXPECT_EQ(rig.tally.first_failure->evidence.sent, sent);
    EXPECT_EQ(rig.tally.first_failure->evidence.received, exception);
}

TEST(LoadConnection, ADroppedConnectionIsCountedAndDialledAgainAfterAPause) {
    Rig rig("fc3:1");
    rig.connection.start(rig.clock.now());
    ASSERT_EQ(rig.requests().size(), 12U);
    rig.ports.device().close();
    rig.connection.on_event(EPOLLIN, rig.clock.now());
    EXPECT_EQ(rig.failures(FailureKind::Dropped), 1U);
    EXPECT_TRUE(rig.ports.pairs.back()->client().is_closed());

    rig.clock.advance(50ms);
    rig.connection.tick(rig.clock.now());
    EXPECT_EQ(rig.ports.pairs.size(), 1U);  // not yet: a device that is down is not hammered
    rig.clock.advance(60ms);
    rig.connection.tick(rig.clock.now());
    ASSERT_EQ(rig.ports.pairs.size(), 2U);
    EXPECT_EQ(rig.requests().size(), 12U);
}

TEST(LoadConnection, ARefusedDialIsOneFailureWithTheReason) {
    Rig rig("fc3:1");
    rig.ports.refuse = ECONNREFUSED;
    rig.connection.start(rig.clock.now());
    EXPECT_EQ(rig.failures(FailureKind::Refused), 1U);
    ASSERT_TRUE(rig.tally.first_failure);
    EXPECT_EQ(rig.tally.first_failure->reason, "cannot connect: connection refused");
    EXPECT_TRUE(rig.ports.pairs.empty());
}

TEST(LoadConnection, RequestsTheDeviceHasNoRoomForWaitForRoom) {
    Rig rig("fc3:1", 4);
    rig.ports.window = 12;  // one request in flight, unread, at a time
    rig.connection.start(rig.clock.now());
    EXPECT_EQ(rig.tally.sent.get(), 4U);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(rig.ports.want_write, i < 3) << i;  // the last request went out whole
        const Bytes sent = rig.requests();
        ASSERT_EQ(sent.size(), 12U) << i;
        EXPECT_EQ(Bytes(sent.begin() + 2, sent.end()), hex("00 00 00 06 01 03 00 00 00 01"));
        rig.connection.on_event(EPOLLOUT, rig.clock.now());
    }
    EXPECT_FALSE(rig.ports.want_write);
    EXPECT_TRUE(rig.requests().empty());
}

}  // namespace
}  // namespace mblab::load
