#pragma once

#include <cstdio>
#include <optional>
#include <string_view>

#include "client/frame_observer.hpp"

// --decode: every frame the client sends (">") and receives ("<"), printed at a chosen depth.
// app: the PDU's fields; frame: also the framing (MBAP header fields); bytes: also the hex.
namespace mblab::cli {

enum class DecodeDepth { App, Frame, Bytes };

std::optional<DecodeDepth> parse_decode_depth(std::string_view name);

class FrameLog final : public client::FrameObserver {
  public:
    FrameLog(std::FILE* out, DecodeDepth depth) : out_(out), depth_(depth) {}

    void on_frame(client::FrameDirection direction, client::Framing framing,
                  std::span<const std::uint8_t> adu) override;
    void on_note(std::string_view note) override;

  private:
    std::FILE* out_;
    DecodeDepth depth_;
};

}  // namespace mblab::cli
