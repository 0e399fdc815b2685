#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "client/link_types.hpp"
#include "conformance/verdict.hpp"

// Evidence as a serial line carried it. Cases are judged in the catalogue's notation, MBAP
// frames, which a line never carries; once a case is judged its evidence is laid out again as the
// frames that crossed the line: address, PDU and CRC low byte first on RTU [SER 2.5.1.2], the
// ':' ... LRC CR LF text on ASCII [SER 2.5.2.1], so a report reads as a line analyser would show
// the traffic.
namespace mblab::conformance {

// The frames of one case as the line carried them, by their catalogue notation: the session
// notes each request it lays out for the line and each answer it lays out in the notation. Only
// the last kKept are kept: a sweep sends tens of thousands, and a failure's evidence is the
// exchange that failed, among the last.
class LineFrames {
  public:
    static constexpr std::size_t kKept = 1024;

    void note(std::span<const std::uint8_t> notation, std::span<const std::uint8_t> wire);
    // The line's bytes of a frame noted in the catalogue's notation; nullptr when not noted.
    const std::vector<std::uint8_t>* wire_of(std::span<const std::uint8_t> notation) const;
    void clear();
    std::size_t size() const { return frames_.size(); }

  private:
    using Frames = std::map<std::vector<std::uint8_t>, std::vector<std::uint8_t>>;
    Frames frames_;
    std::deque<Frames::iterator> order_;  // oldest first
};

// Lays out `exchange`, held in the catalogue's notation, as it crossed a line in `framing`: the
// request and answer as sent and received, the expected frame without the MBAP header and with
// its CRC or LRC (computed when the expected bytes are fixed, XX otherwise), the differing bytes
// numbered from the address. An exchange already in a line's framing is left as it is.
void show_as_on_line(Exchange& exchange, client::Framing framing, const LineFrames& frames);

// A frame as the reports show it: hex bytes ("01 03 00 00 00 01 84 0A"); on ASCII the text
// itself, CR and LF written \r and \n, any other unprintable character \xNN
// (":010300000001FB\r\n").
std::string frame_text(client::Framing framing, std::span<const std::uint8_t> bytes);

// The expected frame as the reports show it, laid out as frame_text lays out a received one.
std::string expected_text(const Exchange& exchange);

// The column in frame_text's (and expected_text's) output where the frame's byte `position`
// starts; each byte takes two columns. On ASCII byte 0 is the address, after the ':'.
std::size_t frame_column(client::Framing framing, std::size_t position);

// How many bytes of `bytes` frame_column places: every byte, or on ASCII those its hex digits
// spell (none when it does not start with ':').
std::size_t frame_cells(client::Framing framing, std::span<const std::uint8_t> bytes);

}  // namespace mblab::conformance
