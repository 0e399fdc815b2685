#include <array>

#include "framer_fuzz.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/crc16.hpp"
#include "protocol/rtu_framer.hpp"

namespace {

using mblab::fuzz::require;
namespace protocol = mblab::protocol;

// Flag bit 0 picks the direction, bit 1 how frames of unknown length end.
protocol::RtuFramer make_framer(std::uint8_t flags) {
    return protocol::RtuFramer(
        (flags & 1U) ? protocol::Direction::Response : protocol::Direction::Request,
        (flags & 2U) ? protocol::RtuFramer::UnknownLength::EndOnCrcMatch
                     : protocol::RtuFramer::UnknownLength::AwaitSilence);
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
    require(protocol::crc16(adu) == 0, "frame with a bad CRC");
    require(event.unit == adu[0], "unit is not the address");
    require(event.pdu.data() == adu.data() + 1 && event.pdu.size() == adu.size() - 3,
            "pdu is not between address and CRC");
    std::array<std::uint8_t, 256> again{};
    const std::size_t written = protocol::write_rtu_adu(event.unit, event.pdu, again);
    require(written == adu.size() && std::memcmp(again.data(), adu.data(), written) == 0,
            "re-encoded frame differs");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return mblab::fuzz::fuzz_framer(data, size, make_framer, check_frame, good_frame);
}
