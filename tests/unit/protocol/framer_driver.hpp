#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "protocol/frame_event.hpp"
#include "protocol/mbap_header.hpp"
#include "support/hex.hpp"

// Drives any framer (MbapFramer, RtuFramer, AsciiFramer) the way a transport does: chunks of a
// chosen size, each drained by calling feed() until it reports NeedMore, and optionally silence
// between segments of the stream. Events are copied out, since their spans die on the next call.
namespace mblab::test {

struct Seen {
    protocol::FrameStatus status = protocol::FrameStatus::NeedMore;
    std::string adu;  // hex
    std::string pdu;  // hex
    unsigned unit = 0;
    protocol::MbapHeader mbap{};  // MBAP events only: the header's fields
    std::string error;

    friend bool operator==(const Seen&, const Seen&) = default;
};

inline void PrintTo(const Seen& seen, std::ostream* os) {
    static constexpr const char* kNames[] = {"NeedMore", "Frame", "Error"};
    *os << kNames[static_cast<int>(seen.status)] << " adu=[" << seen.adu << "] pdu=[" << seen.pdu
        << "] unit=" << seen.unit;
    if (!seen.error.empty()) *os << " error=\"" << seen.error << '"';
}

inline Seen seen(const protocol::FrameEvent& event) {
    const bool mbap = event.header.framing == protocol::Framing::Mbap;
    return Seen{event.status,
                to_hex(event.adu),
                to_hex(event.pdu),
                event.header.unit,
                mbap ? protocol::to_mbap_header(event.header) : protocol::MbapHeader{},
                event.error};
}

inline Seen frame(std::string_view adu_hex, std::string_view pdu_hex, unsigned unit) {
    return Seen{
        protocol::FrameStatus::Frame, to_hex(hex(adu_hex)), to_hex(hex(pdu_hex)), unit, {}, ""};
}

// Feeds one chunk until it is used up, checking the feed() contract on every call.
template <class Framer>
void drain(Framer& framer, std::span<const std::uint8_t> chunk, std::vector<Seen>& out) {
    for (;;) {
        std::size_t consumed = 0;
        const protocol::FrameEvent event = framer.feed(chunk, consumed);
        EXPECT_LE(consumed, chunk.size());
        consumed = std::min(consumed, chunk.size());
        if (event.status == protocol::FrameStatus::NeedMore) {
            EXPECT_EQ(consumed, chunk.size()) << "NeedMore must consume everything";
            return;
        }
        EXPECT_GT(consumed, 0U) << "an event must consume at least one byte";
        if (consumed == 0) return;
        out.push_back(seen(event));
        chunk = chunk.subspan(consumed);
    }
}

template <class Framer>
void silence(Framer& framer, std::vector<Seen>& out) {
    if constexpr (requires { framer.on_silence(); }) {
        const protocol::FrameEvent event = framer.on_silence();
        if (event.status != protocol::FrameStatus::NeedMore) out.push_back(seen(event));
        EXPECT_FALSE(framer.has_partial()) << "silence ends whatever was held";
    }
}

// Feeds each segment in chunks of `chunk` bytes; after every segment but the last comes silence
// (and after the last too when `silence_at_end`).
template <class Framer>
std::vector<Seen> run(Framer framer, const std::vector<std::vector<std::uint8_t>>& segments,
                      std::size_t chunk, bool silence_at_end) {
    std::vector<Seen> out;
    for (std::size_t s = 0; s < segments.size(); ++s) {
        const std::span<const std::uint8_t> bytes = segments[s];
        for (std::size_t at = 0; at < bytes.size(); at += chunk) {
            drain(framer, bytes.subspan(at, std::min(chunk, bytes.size() - at)), out);
        }
        if (s + 1 < segments.size() || silence_at_end) silence(framer, out);
    }
    return out;
}

// Runs the stream whole and then in chunks of 1, 2, 3, 5 and 64 bytes; every way must see the
// same events. Returns them.
template <class Framer>
std::vector<Seen> run_all_chunkings(const Framer& prototype,
                                    const std::vector<std::vector<std::uint8_t>>& segments,
                                    bool silence_at_end = false) {
    std::size_t longest = 1;
    for (const auto& segment : segments)
        longest = std::max(longest, segment.size());
    const std::vector<Seen> whole = run(prototype, segments, longest, silence_at_end);
    for (std::size_t chunk : {1, 2, 3, 5, 64}) {
        EXPECT_EQ(run(prototype, segments, chunk, silence_at_end), whole)
            << "fed in chunks of " << chunk << " bytes";
    }
    return whole;
}

template <class Framer>
std::vector<Seen> run_all_chunkings(const Framer& prototype, std::span<const std::uint8_t> stream) {
    const std::vector<std::vector<std::uint8_t>> one_segment{{stream.begin(), stream.end()}};
    return run_all_chunkings(prototype, one_segment);
}

inline std::vector<std::uint8_t> concat(std::initializer_list<std::vector<std::uint8_t>> parts) {
    std::vector<std::uint8_t> out;
    for (const auto& part : parts)
        out.insert(out.end(), part.begin(), part.end());
    return out;
}

}  // namespace mblab::test
