#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/frame_event.hpp"
#include "protocol/framer.hpp"

// The receiving half of a serial link without I/O: bytes and the clock in, frames and counted
// line errors out. The owner reads the link, passes each chunk with the time it arrived, and
// calls on_timeout() when deadline() passes first; tests drive it with a manual clock.
namespace mblab::server {

using LineClock = std::chrono::steady_clock;

// Rtu or Ascii: a line speaks one of the serial framings.
using LineFraming = protocol::Framing;

struct LineTiming {
    // RTU: t3.5 of silence ends a frame. ASCII: the inter-character timeout drops an unfinished
    // frame. RTU over TCP: how long an unfinished frame may wait for the rest of its bytes.
    std::chrono::microseconds silence{1750};
    // RTU: a gap over t1.5 inside a frame spoils it [SER 2.5.1.1]; 0 leaves gaps unchecked.
    // Off by default: USB adapters deliver a frame in packets with gaps over t1.5, so enforcing
    // it drops good frames from real masters.
    std::chrono::microseconds char_gap{0};
};

// How a dropped frame counts on the line (FC 08 sub 0C counts both).
enum class LineError : std::uint8_t {
    None,        // not an error, or one more error in a noise burst already counted
    Checksum,    // bad CRC or LRC, bad characters, a frame cut short, an overlong frame
    ShortFrame,  // fewer than 4 RTU bytes before silence, or a frame spoiled by a t1.5 gap
};

struct LineEvent {
    // Frame: a request (or a response, for a master); Error: a dropped frame, for logs.
    protocol::FrameEvent frame;
    LineError error = LineError::None;  // what to count for an Error

    bool is_frame() const { return frame.is_frame(); }
    bool is_error() const { return frame.is_error(); }
    bool empty() const { return frame.status == protocol::FrameStatus::NeedMore; }
};

class SerialLineReceiver {
  public:
    SerialLineReceiver(LineFraming framing, LineTiming timing, protocol::Direction direction,
                       protocol::RtuFramer::UnknownLength unknown_length =
                           protocol::RtuFramer::UnknownLength::AwaitSilence);

    // Bytes that arrived at `now`. They must stay unchanged until next() comes back empty.
    void receive(std::span<const std::uint8_t> bytes, LineClock::time_point now);
    // The next event from the received bytes (a silence before them comes first); empty once
    // they are used up. Event spans stay valid until the next call on the receiver.
    LineEvent next();
    // When silence would end or drop what is held; time_point::max() when nothing waits.
    LineClock::time_point deadline() const;
    // Call once deadline() has passed without bytes: the frame or error the silence gives.
    LineEvent on_timeout(LineClock::time_point now);

    bool has_partial() const;
    // When the last bytes arrived.
    LineClock::time_point last_byte_time() const { return last_byte_; }
    // Forgets held bytes and any pending input (a master starting a new transaction).
    void reset();

    // ASCII: the character after CR that ends a frame (FC 08 sub 03 changes it).
    void set_ascii_delimiter(std::uint8_t end);
    std::uint8_t ascii_delimiter() const;

  private:
    LineEvent silence();
    LineEvent classify(const protocol::FrameEvent& event, std::size_t held_before);
    LineEvent count_once(const protocol::FrameEvent& event, LineError error);
    bool is_rtu() const { return framer_.framing() == protocol::Framing::Rtu; }

    protocol::Framer framer_;
    LineTiming timing_;
    std::span<const std::uint8_t> input_;
    std::size_t position_ = 0;
    LineClock::time_point last_byte_{};
    std::size_t held_ = 0;        // bytes the RTU framer holds in the current frame
    bool in_burst_ = false;       // bytes came since the last silence
    bool silence_due_ = false;    // the bytes in input_ came after a silence
    bool broken_ = false;         // a t1.5 gap spoiled the frame being received
    bool error_counted_ = false;  // RTU: this noise burst has been counted once
};

}  // namespace mblab::server
