#include <array>

#include "framer_fuzz.hpp"
#include "protocol/adu.hpp"
#include "protocol/mbap_framer.hpp"

namespace {

using mblab::fuzz::require;
namespace protocol = mblab::protocol;

void check_frame(const protocol::FrameEvent& event) {
    const auto& adu = event.adu;
    require(adu.size() >= 7 && adu.size() <= 260, "MBAP frame size out of limits");
    const protocol::MbapHeader header = protocol::read_mbap_header(adu);
    require(event.header == protocol::to_adu_header(header), "header fields are not the frame's");
    require(mblab::fuzz::clean_or_excused(event, header.protocol_id == 0 && header.length >= 2),
            "frame with protocol id != 0 or no function code, and no violation");
    require(header.length + 6U == adu.size(), "frame size disagrees with its length");
    require(event.header.unit == header.unit_id, "unit is not the header's");
    require(event.pdu.data() == adu.data() + 7 && event.pdu.size() == adu.size() - 7,
            "pdu is not the rest of the frame");
    // Round trip: writing the PDU again gives the same bytes.
    std::array<std::uint8_t, 260> again{};
    const std::size_t written = protocol::write_adu(event.header, event.pdu, again);
    require(written == adu.size() && std::memcmp(again.data(), adu.data(), written) == 0,
            "re-encoded frame differs");
}

// What mbap_resync_offset finds reads, from there, as whole frames only: the framer reports
// one or more frames and no error up to the end.
void check_resync(std::span<const std::uint8_t> bytes) {
    const std::size_t offset = protocol::mbap_resync_offset(bytes);
    require(offset <= bytes.size(), "resync offset past the end");
    if (offset == bytes.size()) return;
    protocol::MbapFramer framer;
    auto rest = bytes.subspan(offset);
    std::size_t frames = 0;
    while (!rest.empty()) {
        std::size_t consumed = 0;
        const auto event = framer.feed(rest, consumed);
        require(event.status != protocol::FrameStatus::Error, "resync offset leads to an error");
        if (event.status == protocol::FrameStatus::Frame) ++frames;
        rest = rest.subspan(consumed);
    }
    require(frames > 0, "resync offset without a whole frame");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::uint8_t kGood[] = {0, 1, 0, 0, 0, 2, 1, 7};
    check_resync(std::span<const std::uint8_t>(data, size));
    return mblab::fuzz::fuzz_framer(
        data, size, {.framing = protocol::Framing::Mbap}, check_frame,
        [](std::uint8_t) { return std::span<const std::uint8_t>(kGood); });
}
