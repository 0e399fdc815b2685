#pragma once

#include <chrono>
#include <cstdint>
#include <span>

// The master's side of a serial line without I/O [SER 2.4.1]: when the line is free for the
// next request, how long the request waits for its answer, and whether a frame heard is that
// answer. The owner writes the request once line_free_at() has passed, says when its last byte
// left, hands over every frame heard and wakes the master at deadline(); tests drive it with a
// manual clock.
//
//   Idle --request (unicast)--> WaitingReply --its answer--> Idle
//                                    |  a frame from another address or for another function:
//                                    |  discarded, the response timer keeps running
//                                    +--response timeout--> Idle (no answer)
//   Idle --request (broadcast)--> Turnaround --turnaround delay--> Idle
//
// A frame heard while Idle is late (its request timed out) or unasked, and discarded.
namespace mblab::transport {

class SerialMaster {
  public:
    using Clock = std::chrono::steady_clock;

    struct Timing {
        // Silence between two frames on the line: t3.5 for RTU [SER 2.5.1.1]; 0 for ASCII,
        // whose frames are delimited by characters.
        std::chrono::microseconds inter_frame{0};
        // After a broadcast, before the next request: the devices execute it meanwhile.
        std::chrono::microseconds turnaround{0};
        // From the request's last byte on the wire to its answer's last byte.
        std::chrono::milliseconds response_timeout{1000};
    };

    enum class State : std::uint8_t { Idle, WaitingReply, Turnaround };

    enum class Verdict : std::uint8_t {
        Answer,         // the awaited request's answer (or its exception): the exchange ends
        OtherAddress,   // from an address not asked: discarded, the timer keeps running
        OtherFunction,  // the asked address, another function code: discarded likewise
        Unasked,        // nothing awaited an answer: late or unsolicited, discarded
    };

    enum class Timeout : std::uint8_t {
        None,
        NoAnswer,       // the response timeout ran out: the exchange ends unanswered
        TurnaroundOver  // a broadcast's turnaround ended: the line takes the next request
    };

    explicit SerialMaster(Timing timing) : timing_(timing) {}

    State state() const { return state_; }
    // The earliest the next request may start: the inter-frame silence after the last byte sent
    // or heard, and the end of a broadcast's turnaround.
    Clock::time_point line_free_at() const { return line_free_at_; }

    // A request's last byte left at `now`: to `unit` (0: a broadcast, which none answers) for
    // `function`. The response timer starts.
    void request_sent(std::uint8_t unit, std::uint8_t function, Clock::time_point now);
    // Bytes heard at `now`, whole frames or noise: the line is busy until a silence after them.
    void heard(Clock::time_point now);
    // A whole frame from `unit`, its PDU `pdu` (function code first), heard at `now`.
    Verdict on_frame(std::uint8_t unit, std::span<const std::uint8_t> pdu, Clock::time_point now);

    // When on_time() has something to do; time_point::max() when nothing waits.
    Clock::time_point deadline() const;
    Timeout on_time(Clock::time_point now);

  private:
    void free_line_after(Clock::time_point at);

    Timing timing_;
    State state_ = State::Idle;
    std::uint8_t unit_ = 0;
    std::uint8_t function_ = 0;
    Clock::time_point deadline_ = Clock::time_point::max();
    Clock::time_point line_free_at_{};
};

}  // namespace mblab::transport
