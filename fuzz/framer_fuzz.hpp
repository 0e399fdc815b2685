#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <span>

#include "protocol/frame_event.hpp"
#include "protocol/framer.hpp"

// Shared driver of the framer fuzz targets, one per framing of protocol::Framer. The first two
// input bytes seed the choices (chunk sizes, silence points, framer options: bit 2 of the first
// makes the framer lenient); the rest is the byte stream. Every contract of feed()
// is checked, and every reported frame must be exactly the last bytes of the stream delivered so
// far, so a framer can neither invent bytes nor read past its input.
namespace mblab::fuzz {

inline void require(bool condition, const char* what) {
    if (!condition) {
        std::fprintf(stderr, "framer contract broken: %s\n", what);
        std::abort();
    }
}

// Small deterministic generator for the choices, so a crash replays from its input alone.
class Choices {
  public:
    explicit Choices(std::uint32_t seed) : state_(seed * 2654435761U + 1U) {}
    std::uint32_t next() {
        state_ ^= state_ << 13;
        state_ ^= state_ >> 17;
        state_ ^= state_ << 5;
        return state_;
    }
    // Mostly small chunks (byte-at-a-time paths), sometimes large ones (zero-copy paths).
    std::size_t chunk() {
        const std::uint32_t r = next();
        return (r & 3U) == 0 ? 1 + (r >> 2) % 1024 : 1 + (r >> 2) % 9;
    }
    bool one_in(unsigned n) { return next() % n == 0; }

  private:
    std::uint32_t state_;
};

struct Stream {
    std::span<const std::uint8_t> bytes;
    std::uint8_t flags = 0;  // framer options, chosen by the target
    std::uint16_t seed = 0;
};

inline bool split(const std::uint8_t* data, std::size_t size, Stream& out) {
    if (size < 2) return false;
    out.flags = data[0];
    out.seed = static_cast<std::uint16_t>(data[0] << 8 | data[1]);
    out.bytes = {data + 2, size - 2};
    return true;
}

// An event's adu must be the bytes just before `end` in the stream.
inline void require_suffix(const protocol::FrameEvent& event,
                           std::span<const std::uint8_t> so_far) {
    require(event.adu.size() <= so_far.size(), "adu longer than the stream");
    const auto tail = so_far.last(event.adu.size());
    require(event.adu.empty() || std::memcmp(event.adu.data(), tail.data(), tail.size()) == 0,
            "adu is not the last bytes fed");
}

template <class CheckFrame>
void handle(const protocol::FrameEvent& event, std::span<const std::uint8_t> so_far,
            CheckFrame& check_frame) {
    if (event.status == protocol::FrameStatus::Error) {
        require(event.error != nullptr && event.error[0] != '\0', "error without a reason");
        require_suffix(event, so_far);
    } else if (event.status == protocol::FrameStatus::Frame) {
        require_suffix(event, so_far);
        check_frame(event);
    }
}

// Feeds the stream in chosen chunks, with silence at chosen points when the framer has it.
template <class CheckFrame>
void drive(protocol::Framer& framer, const Stream& stream, CheckFrame check_frame) {
    Choices choices(stream.seed);
    std::size_t pos = 0;
    while (pos < stream.bytes.size()) {
        const std::size_t chunk = std::min(choices.chunk(), stream.bytes.size() - pos);
        auto rest = stream.bytes.subspan(pos, chunk);
        std::size_t fed = pos;
        for (;;) {
            std::size_t consumed = 0;
            const protocol::FrameEvent event = framer.feed(rest, consumed);
            require(consumed <= rest.size(), "consumed past the input");
            fed += consumed;
            rest = rest.subspan(consumed);
            if (event.status == protocol::FrameStatus::NeedMore) {
                require(rest.empty(), "NeedMore left input unconsumed");
                break;
            }
            require(consumed > 0, "an event consumed nothing");
            handle(event, stream.bytes.first(fed), check_frame);
        }
        pos += chunk;
        if (choices.one_in(3)) {
            const bool held = framer.has_partial();
            handle(framer.on_silence(), stream.bytes.first(pos), check_frame);
            // MBAP frames end by their length alone: silence changes nothing there.
            const bool ends = framer.framing() != protocol::Framing::Mbap;
            require(framer.has_partial() == (held && !ends), "silence ended the wrong frames");
        }
    }
}

inline bool lenient(std::uint8_t flags) {
    return (flags & 4U) != 0;
}

// A frame a lenient framer let through must say why a strict one would not have.
inline bool clean_or_excused(const protocol::FrameEvent& event, bool clean) {
    return clean ? *event.violation == '\0' : *event.violation != '\0';
}

// The whole of a framer target: builds the framer from the flags, drives it over the stream,
// then checks that after reset() it still takes a good frame, whatever came before.
template <class CheckFrame, class GoodFrame>
int fuzz_framer(const std::uint8_t* data, std::size_t size, protocol::FramerOptions options,
                CheckFrame check_frame, GoodFrame good_frame) {
    Stream stream;
    if (!split(data, size, stream)) return 0;
    options.lenient = lenient(stream.flags);
    protocol::Framer framer(options);
    drive(framer, stream, [&](const protocol::FrameEvent& event) {
        require(event.header.framing == options.framing, "header of another framing");
        check_frame(event);
    });
    framer.reset();
    std::size_t consumed = 0;
    require(framer.feed(good_frame(stream.flags), consumed).status == protocol::FrameStatus::Frame,
            "good frame refused after reset");
    return 0;
}

}  // namespace mblab::fuzz
