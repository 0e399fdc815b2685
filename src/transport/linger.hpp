#pragma once

#include <algorithm>
#include <chrono>

namespace mblab::transport {

// How long a connection that ended its output still reads and drops what the peer sends. A
// socket closed with input unread is answered with a reset (RFC 1122 4.2.2.13), and a reset
// throws away the answers the peer has not read yet; so the server reads on until the peer ends
// too, or sends nothing for kQuiet. A peer that keeps sending keeps it reading, kAtMost in all:
// its bytes would otherwise meet a closed socket. One wake reads at most kReadsPerWake pieces,
// so a flood cannot hold the loop.
class Linger {
  public:
    using Clock = std::chrono::steady_clock;
    static constexpr auto kQuiet = std::chrono::seconds(2);
    static constexpr auto kAtMost = std::chrono::seconds(30);
    static constexpr int kReadsPerWake = 16;

    void start(Clock::time_point now) {
        until_ = now + kAtMost;
        deadline_ = now + kQuiet;
    }
    // The peer sent something more.
    void heard(Clock::time_point now) { deadline_ = std::min(now + kQuiet, until_); }

    bool active() const { return deadline_ != Clock::time_point::max(); }
    // When to let the connection go; time_point::max() before start().
    Clock::time_point deadline() const { return deadline_; }
    bool over(Clock::time_point now) const { return now >= deadline_; }

  private:
    Clock::time_point deadline_ = Clock::time_point::max();
    Clock::time_point until_ = Clock::time_point::max();
};

}  // namespace mblab::transport
