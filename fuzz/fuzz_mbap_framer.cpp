#include <array>

#include "framer_fuzz.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/mbap_framer.hpp"

namespace {

using mblab::fuzz::require;
namespace protocol = mblab::protocol;

void check_frame(const protocol::FrameEvent& event) {
    const auto& adu = event.adu;
    require(adu.size() >= 8 && adu.size() <= 260, "MBAP frame size out of limits");
    const protocol::MbapHeader header = protocol::read_mbap_header(adu);
    require(header == event.mbap, "mbap is not the frame's header");
    require(header.protocol_id == 0, "frame with protocol id != 0");
    require(header.length + 6U == adu.size(), "frame size disagrees with its length");
    require(event.unit == header.unit_id, "unit is not the header's");
    require(event.pdu.data() == adu.data() + 7 && event.pdu.size() == adu.size() - 7,
            "pdu is not the rest of the frame");
    // Round trip: writing the PDU again gives the same bytes.
    std::array<std::uint8_t, 260> again{};
    const std::size_t written = protocol::write_mbap_adu(header, event.pdu, again);
    require(written == adu.size() && std::memcmp(again.data(), adu.data(), written) == 0,
            "re-encoded frame differs");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::uint8_t kGood[] = {0, 1, 0, 0, 0, 2, 1, 7};
    return mblab::fuzz::fuzz_framer(
        data, size, [](std::uint8_t) { return protocol::MbapFramer{}; }, check_frame,
        [](std::uint8_t) { return std::span<const std::uint8_t>(kGood); });
}
