#include "protocol/mbap_header.hpp"

namespace mblab::protocol {

namespace {
std::uint16_t be16(std::span<const std::uint8_t> bytes, std::size_t at) {
    return static_cast<std::uint16_t>(bytes[at] << 8 | bytes[at + 1]);
}
}  // namespace

MbapHeader read_mbap_header(std::span<const std::uint8_t> bytes) {
    return MbapHeader{be16(bytes, 0), be16(bytes, 2), be16(bytes, 4), bytes[6]};
}

std::optional<Adu> read_mbap_frame(std::span<const std::uint8_t> bytes) {
    constexpr std::size_t kHeader = 7;
    if (bytes.size() < kHeader) return std::nullopt;
    return Adu{to_adu_header(read_mbap_header(bytes)), bytes.subspan(kHeader)};
}

}  // namespace mblab::protocol
