#include <array>

#include "framer_fuzz.hpp"
#include "protocol/adu.hpp"
#include "protocol/crc16.hpp"

namespace {

using mblab::fuzz::require;
namespace protocol = mblab::protocol;

// Flag bit 0 picks the direction, bit 1 how frames of unknown length end.
protocol::FramerOptions options_of(std::uint8_t flags) {
    return {
        .framing = protocol::Framing::Rtu,
        .direction = (flags & 1U) ? protocol::Direction::Response : protocol::Direction::Request,
        .unknown_length = (flags & 2U) ? protocol::RtuFramer::UnknownLength::EndOnCrcMatch
                                       : protocol::RtuFramer::UnknownLength::AwaitSilence};
}

std::span<const std::uint8_t> good_frame(std::uint8_t flags) {
    static const std::uint8_t kRequest[] = {0x01, 0x07, 0x41, 0xE2};
    static const std::uint8_t kResponse[] = {0x01, 0x83, 0x02, 0xC0, 0xF1};
    if (flags & 1U) return kResponse;
    return kRequest;
}

void check_frame(const protocol::FrameEvent& event) {
    const auto& adu = event.adu;
    require(adu.size() >= 4 && adu.size() <= 256, "RTU frame size out of limits");
    const bool clean = protocol::crc16(adu) == 0;
    require(mblab::fuzz::clean_or_excused(event, clean), "frame with a bad CRC and no violation");
    require(event.header.unit == adu[0], "unit is not the address");
    require(event.pdu.data() == adu.data() + 1 && event.pdu.size() == adu.size() - 3,
            "pdu is not between address and CRC");
    std::array<std::uint8_t, 256> again{};
    const std::size_t written = protocol::write_adu(event.header, event.pdu, again);
    require(
        written == adu.size() && (!clean || std::memcmp(again.data(), adu.data(), written) == 0),
        "re-encoded frame differs");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::uint8_t flags = size > 0 ? data[0] : 0;
    return mblab::fuzz::fuzz_framer(data, size, options_of(flags), check_frame, good_frame);
}
