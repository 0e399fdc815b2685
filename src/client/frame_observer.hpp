#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "client/link.hpp"

namespace mblab::client {

enum class FrameDirection : std::uint8_t { Sent, Received };

// Sees every frame the client sends or receives, whole, in the link's framing (for --decode).
class FrameObserver {
  public:
    virtual ~FrameObserver() = default;
    virtual void on_frame(FrameDirection direction, Framing framing,
                          std::span<const std::uint8_t> adu) = 0;
    // Something the client did that no frame shows: a retry, a discarded late answer.
    virtual void on_note(std::string_view note) = 0;
};

}  // namespace mblab::client
