#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client/link_types.hpp"
#include "protocol/framer.hpp"

// The receiving half of a client link without I/O: the bytes a link reads go in, whole frames and
// framing errors come out as Received, with the wire bytes each one took. The links own the
// descriptor and the clock; this owns the framer and what it has not finished with.
namespace mblab::client {

class FrameReader {
  public:
    explicit FrameReader(const protocol::FramerOptions& options) : framer_(options) {}

    void add(std::span<const std::uint8_t> bytes);
    // The next frame or framing error from the bytes added; nullopt once they are used up.
    std::optional<Received> next();
    // The link went quiet (the caller's silence timer): the frame or error that ends, if any.
    std::optional<Received> on_silence();
    // Hands over everything held, frame started or not, and forgets it (timeout, close).
    Received take(ReceiveStatus status, std::string detail = {});

    // Bytes of an unfinished frame are held.
    bool has_partial() const { return framer_.has_partial(); }
    bool empty() const { return pending_.empty() && partial_.empty(); }
    protocol::Framing framing() const { return framer_.framing(); }
    void reset();

  private:
    // `consumed`: the bytes at the front of pending_ the event took (already in partial_).
    std::optional<Received> cut(const protocol::FrameEvent& event, std::size_t consumed);

    protocol::Framer framer_;
    std::vector<std::uint8_t> pending_;  // added, not yet given to the framer
    std::vector<std::uint8_t> partial_;  // given to the framer, frame not finished
};

}  // namespace mblab::client
