#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "client/raw_link.hpp"
#include "load/answer.hpp"
#include "load/connection_port.hpp"
#include "load/exchanges.hpp"
#include "load/plan.hpp"
#include "load/tally.hpp"
#include "protocol/framer.hpp"
#include "security/tls_channel.hpp"
#include "support/prng.hpp"
#include "transport/channel.hpp"
#include "transport/tls_stream.hpp"

namespace mblab::load {

// What the connections of one worker thread share.
struct WorkerContext {
    const LoadPlan& plan;
    ConnectionPorts& ports;
    LoadClock::time_point start;
    std::chrono::nanoseconds send_interval{0};  // per connection, from --rate; 0: none
    bool running = true;                        // false once the run drains: no new requests
};

// One connection of a load run, closed loop: it keeps up to its window of requests in flight,
// sends the next as each answer comes, judges every answer, times out the ones that do not
// come and reconnects when the device drops it. Transaction ids name a slot of the window and
// its generation, so an answer finds its request without a search, and an answer that comes
// after its request timed out is recognised and not counted twice. After setup nothing is
// allocated, except to keep the evidence of the node's first failure.
class LoadConnection {
  public:
    enum class Role : std::uint8_t {
        Tests,    // the node's protocol tests, in catalogue order, one at a time
        Traffic,  // the generator: requests drawn from the mix, --pipeline in flight
    };

    LoadConnection(WorkerContext& context, NodeTally& tally, std::size_t node, Role role,
                   std::uint64_t seed);
    ~LoadConnection();
    LoadConnection(const LoadConnection&) = delete;
    LoadConnection& operator=(const LoadConnection&) = delete;

    void start(LoadClock::time_point now) { connect(now); }
    void on_event(std::uint32_t events, LoadClock::time_point now);
    // Timeouts, reconnects and paced sends; called every few milliseconds.
    void tick(LoadClock::time_point now);
    // Nothing in flight and no connection being made: the run may end.
    bool settled() const;

  private:
    enum class State : std::uint8_t { Closed, Connecting, Handshaking, Open, Done };
    struct Slot {
        LoadClock::time_point sent_at{};
        std::uint32_t exchange = 0;
        std::uint16_t tid = 0;
        std::uint16_t generation = 0;
        std::uint16_t expired_tid = 0;
        bool active = false;
        bool has_expired = false;
    };

    void connect(LoadClock::time_point now);
    void finish_connect(LoadClock::time_point now);
    void opened(LoadClock::time_point now);
    void start_traffic(LoadClock::time_point now);
    // mbaps://: TLS between the socket and in_/out_.
    void start_tls(LoadClock::time_point now);
    // Moves the handshake on at each wake-up; traffic starts once it is over.
    void handshake(LoadClock::time_point now);
    // Reads the channel into in_; false when nothing came or the connection was lost.
    bool receive(LoadClock::time_point now);
    void disconnect(LoadClock::time_point now);
    void lost(LoadClock::time_point now, const char* detail);

    void fill(LoadClock::time_point now);
    void flush(LoadClock::time_point now);
    void read(LoadClock::time_point now);
    void answer(std::span<const std::uint8_t> frame, LoadClock::time_point now);
    void expire(LoadClock::time_point now);

    // The next exchange to send; false when none may go (every test case is N/A here).
    bool next_exchange(std::uint32_t& out);
    Slot& take_slot();
    void release(Slot& slot);
    Slot* find_slot(std::uint16_t tid);
    Slot* oldest_slot();
    std::span<const std::uint8_t> held() const {
        return {in_.data() + in_begin_, in_end_ - in_begin_};
    }

    // Counts a failure (count_failure); `slot` names the exchange, when one was sent.
    void fail(FailureKind kind, const Slot* slot, const LoadSeen& seen, LoadClock::time_point now,
              std::string_view reason = {});
    void set_write_interest(bool want);

    WorkerContext& context_;
    NodeTally& tally_;
    const LoadTarget& target_;
    Role role_;
    Prng prng_;
    State state_ = State::Closed;
    std::unique_ptr<ConnectionPort> port_;
    bool want_write_ = false;
    LoadClock::time_point retry_at_{};
    LoadClock::time_point connect_deadline_{};
    LoadClock::time_point next_send_{};

    std::size_t window_ = 1;
    unsigned slot_bits_ = 0;
    std::vector<Slot> slots_;
    std::vector<std::uint16_t> free_slots_;
    std::size_t outstanding_ = 0;
    LoadClock::time_point earliest_deadline_ = LoadClock::time_point::max();
    std::size_t test_cursor_ = 0;

    // Cuts answers out of in_; holds nothing between reads.
    protocol::Framer framer_{{.framing = protocol::Framing::Mbap}};
    std::vector<std::uint8_t> in_;
    std::size_t in_begin_ = 0;
    std::size_t in_end_ = 0;
    std::vector<std::uint8_t> out_;
    std::size_t out_begin_ = 0;
    std::size_t out_end_ = 0;

    // The port's channel, or TLS over it (then tls_ points into it).
    std::unique_ptr<transport::Channel> channel_;
    transport::TlsStream* tls_ = nullptr;
    // The last session, offered again at a reconnect so the device can resume it.
    SSL_SESSION* session_ = nullptr;
};

}  // namespace mblab::load
