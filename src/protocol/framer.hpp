#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>

#include "protocol/adu.hpp"
#include "protocol/ascii_framer.hpp"
#include "protocol/frame_error_text.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/mbap_framer.hpp"
#include "protocol/result.hpp"
#include "protocol/rtu_framer.hpp"

namespace mblab::protocol {

struct FramerOptions {
    Framing framing = Framing::Mbap;
    // RTU: whether requests or responses are expected; their layouts give a frame's length.
    Direction direction = Direction::Request;
    // RTU: what ends a frame whose layout gives no length (silence, or also a CRC match on links
    // without silence).
    RtuFramer::UnknownLength unknown_length = RtuFramer::UnknownLength::AwaitSilence;
    // The tester's mode: frames whose extent is known but that a strict framer refuses (MBAP
    // protocol id other than 0 or length 1, a bad CRC or LRC) come through as Frames with
    // FrameEvent::violation saying why, so the device can be judged on what it sent.
    bool lenient = false;
};

// The one place that cuts Modbus frames out of a byte stream, whatever the framing. Every reader
// of a link (server sessions, the client's links, the tester, the load generator, the pcap
// writer) feeds it bytes and tells it about silence; it gives back frames as an ADU header and a
// PDU, or counted errors, without I/O or allocation.
//
// Contract: feed() consumes bytes from `input` (sets `consumed`, never past input.size()) and
// reports the first event; call it again with the rest until it reports NeedMore, which always
// means everything was consumed. Every Frame or Error consumes at least one byte. Event spans stay
// valid until the next call on the framer and while the input is unchanged.
class Framer {
  public:
    explicit Framer(const FramerOptions& options);

    FrameEvent feed(std::span<const std::uint8_t> input, std::size_t& consumed);
    // The caller, which owns the clock, saw the line go quiet: RTU ends the held frame (t3.5),
    // ASCII drops it (inter-character timeout). MBAP frames end by their length alone: NeedMore.
    FrameEvent on_silence();
    // Forgets a partial frame (after an error, or before a new transaction).
    void reset();

    // The one frame that `frame` holds from its first byte to its last: bytes a reader already
    // cut, a frame sent or logged. Its header and PDU, or why the bytes are not one whole frame
    // (shorter than any frame, an MBAP protocol id other than 0 or a length field that disagrees
    // with the bytes, a bad CRC or LRC, an ASCII frame that ends early). An empty PDU (MBAP
    // length 1, an RTU address and CRC alone) is no error here: the caller judges it. A partial
    // frame is forgotten; the PDU and the error stay valid as event spans do.
    Result<Adu, const char*> whole_frame(std::span<const std::uint8_t> frame);

    bool has_partial() const;
    Framing framing() const { return framing_; }
    // MBAP: an unfinished frame once its 7 header bytes came, with the PDU bytes so far.
    std::optional<Adu> partial_frame() const;
    // ASCII: the character after CR that ends a frame (FC 08 sub-function 03 changes it).
    void set_ascii_delimiter(std::uint8_t end);
    std::uint8_t ascii_delimiter() const;

  private:
    Result<Adu, const char*> whole_ascii_frame(std::span<const std::uint8_t> frame);

    Framing framing_;
    std::variant<MbapFramer, RtuFramer, AsciiFramer> impl_;
    FrameErrorText error_;
};

}  // namespace mblab::protocol
