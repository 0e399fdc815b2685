#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "protocol/mbap_header.hpp"
#include "server/reply_queue.hpp"

namespace mblab::server {

// The start of a Modbus/TCP frame whose bytes have not all come, remembered so that it can be
// answered 03 [CTP 9.1.3] once its wait runs out: the framer holds the bytes, this keeps
// the header, the function code and when the frame began. It also stands in for the framer while
// the body of an overlong header (MBAP length over 254, which the framer gives up on) is skipped.
class UnfinishedMbapFrame {
  public:
    // Nothing is held: no frame has begun, or the last one completed.
    bool empty() const { return bytes_ == 0 && !overlong_; }
    bool overlong() const { return overlong_; }
    // Its first byte, for ServerOptions::frame_limit.
    Clock::time_point started() const { return started_; }

    // `count` more bytes of it came; `frame` is what the framer read of it so far.
    void add(std::size_t count, const std::optional<protocol::Adu>& frame, Clock::time_point now);
    // The framer refused `header` for its length: the body is skipped here instead.
    void begin_overlong(const protocol::MbapHeader& header, Clock::time_point started);
    // Bytes that followed an overlong header; false once they exceed any PDU (a flood, not a
    // length typo).
    bool skip(std::span<const std::uint8_t> bytes);

    // The header and function code for its 03, when it got that far and its protocol id is 0.
    struct Answerable {
        protocol::MbapHeader header;
        std::uint8_t function = 0;
    };
    std::optional<Answerable> answerable() const;
    // Where whole requests begin again in an overlong frame's kept body: a client may have sent
    // them during the wait without waiting for the 03. Empty when there are none.
    std::span<const std::uint8_t> requests_after_body() const;

    void clear();

  private:
    std::size_t bytes_ = 0;  // of the frame so far, header included
    Clock::time_point started_{};
    std::optional<protocol::MbapHeader> header_;
    std::optional<std::uint8_t> function_;
    bool overlong_ = false;
    std::size_t skipped_ = 0;
    // What followed an overlong header (function code first), up to a PDU: that frame's body, and
    // perhaps requests sent after it. Allocated only for such a frame.
    std::vector<std::uint8_t> body_;
};

}  // namespace mblab::server
