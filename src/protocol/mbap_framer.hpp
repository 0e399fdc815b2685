#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "protocol/frame_error_text.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::protocol {

// Splits a Modbus/TCP byte stream into MBAP frames. Sans-I/O and allocation-free: it holds at
// most one unfinished frame (260 bytes).
//
// Errors:
// - length < 2 or > 254 (an ADU over 260 bytes): Error after the 7 header bytes; the framer
//   resets. The stream cannot be trusted after this, so a server closes the connection.
// - protocol id != 0 with a sane length: the framer takes the frame's declared bytes and then
//   reports Error (with adu, pdu and header filled, so a caller can log what it dropped). The
//   stream stays in step, so a server keeps serving [TCPG 4.4.2.2].
//
// Lenient (the tester's mode): a protocol id other than 0 and a length of 1 (a unit id and no
// PDU) come through as Frames with `violation` saying what a strict framer refuses, so that the
// tester can judge what a device sent. Lengths of 0 or over 254 stay errors: they give no frame.
class MbapFramer {
  public:
    explicit MbapFramer(bool lenient = false) : lenient_(lenient) {}

    // Consumes bytes from `input` (sets `consumed`, never past input.size()) and reports the
    // first event. Call again with the unconsumed rest until it reports NeedMore, which always
    // means everything was consumed. Every Frame or Error consumes at least one byte.
    // A whole frame inside `input` is reported without copying (adu points into `input`).
    FrameEvent feed(std::span<const std::uint8_t> input, std::size_t& consumed);

    // Some bytes of an unfinished frame are held (a server's idle timer wants to know).
    bool has_partial() const { return held_ > 0; }
    // The unfinished frame once its 7 header bytes arrived: its header and the PDU bytes so far
    // (a server answers a frame that never completes by its function code).
    std::optional<Adu> partial_frame() const;
    void reset() { held_ = 0; }

  private:
    // Checks the length of a complete header; returns an Error event or nullopt.
    std::optional<FrameEvent> check_length(const MbapHeader& header);
    FrameEvent finish(std::span<const std::uint8_t> adu);

    std::array<std::uint8_t, limits::kMaxTcpAdu> buffer_{};
    std::size_t held_ = 0;
    bool lenient_ = false;
    FrameErrorText error_;
};

// Where whole frames start again in `bytes` that followed a header whose length no frame can
// have (MBAP length over 254): that frame's end is unknown, but a client that sent further
// requests without waiting for its 03 must not lose them. Returns the first offset from which the
// bytes read as one or more whole frames of protocol id 0 and a sane length, possibly followed by
// the beginning of another, up to the end; bytes.size() when there is none (the bytes are that
// frame's body).
std::size_t mbap_resync_offset(std::span<const std::uint8_t> bytes);

}  // namespace mblab::protocol
