#include "protocol/framer.hpp"

#include "protocol/crc16.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::protocol {

namespace {

constexpr std::size_t kRtuOverhead = 3;  // address + CRC

std::variant<MbapFramer, RtuFramer, AsciiFramer> make(const FramerOptions& options) {
    switch (options.framing) {
        case Framing::Rtu:
            return RtuFramer(options.direction, options.unknown_length, options.lenient);
        case Framing::Ascii:
            return AsciiFramer(options.lenient);
        case Framing::Mbap:
            break;
    }
    return MbapFramer(options.lenient);
}

}  // namespace

Framer::Framer(const FramerOptions& options) : framing_(options.framing), impl_(make(options)) {}

FrameEvent Framer::feed(std::span<const std::uint8_t> input, std::size_t& consumed) {
    // The MBAP framer is the server's hot path: no visit for it.
    if (auto* mbap = std::get_if<MbapFramer>(&impl_)) return mbap->feed(input, consumed);
    return std::visit([&](auto& framer) { return framer.feed(input, consumed); }, impl_);
}

FrameEvent Framer::on_silence() {
    if (auto* rtu = std::get_if<RtuFramer>(&impl_)) return rtu->on_silence();
    if (auto* ascii = std::get_if<AsciiFramer>(&impl_)) return ascii->on_silence();
    return FrameEvent{};
}

void Framer::reset() {
    std::visit([](auto& framer) { framer.reset(); }, impl_);
}

Result<Adu, const char*> Framer::whole_frame(std::span<const std::uint8_t> frame) {
    reset();
    switch (framing_) {
        case Framing::Mbap: {
            const auto read = read_mbap_frame(frame);
            if (!read) {
                return error_.format(
                    "the frame is %zu bytes long, shorter than an MBAP header (%zu)", frame.size(),
                    limits::kMbapHeader);
            }
            const auto& header = read->header;
            if (header.protocol_id != kModbusProtocolId) {
                return error_.format("MBAP protocol id is 0x%04X, expected 0x0000 (Modbus)",
                                     unsigned{header.protocol_id});
            }
            if (header.length != read->pdu.size() + 1) {
                return error_.format("MBAP length %u disagrees with the %zu bytes after it",
                                     unsigned{header.length}, read->pdu.size() + 1);
            }
            return *read;
        }
        case Framing::Rtu:
            if (frame.size() < kRtuOverhead) {
                return error_.format("the frame is %zu bytes long, too short for RTU",
                                     frame.size());
            }
            if (crc16(frame) != 0) return "the RTU frame's CRC does not match";
            return Adu{{Framing::Rtu, frame.front()},
                       frame.subspan(1, frame.size() - kRtuOverhead)};
        case Framing::Ascii:
            return whole_ascii_frame(frame);
    }
    return "unknown framing";
}

Result<Adu, const char*> Framer::whole_ascii_frame(std::span<const std::uint8_t> frame) {
    std::size_t consumed = 0;  // the frame's extent is event.adu: characters around it count
    const FrameEvent event = std::get<AsciiFramer>(impl_).feed(frame, consumed);
    const char* broken = event.is_error() ? event.error : event.violation;
    if (*broken != '\0') {
        reset();
        return error_.format("the ASCII frame is broken: %s", broken);
    }
    if (!event.is_frame() || event.adu.size() != frame.size()) {
        reset();
        return "the bytes are not one whole ASCII frame";
    }
    return Adu{event.header, event.pdu};
}

bool Framer::has_partial() const {
    return std::visit([](const auto& framer) { return framer.has_partial(); }, impl_);
}

std::optional<Adu> Framer::partial_frame() const {
    if (const auto* mbap = std::get_if<MbapFramer>(&impl_)) return mbap->partial_frame();
    return std::nullopt;
}

void Framer::set_ascii_delimiter(std::uint8_t end) {
    if (auto* ascii = std::get_if<AsciiFramer>(&impl_)) ascii->set_end_delimiter(end);
}

std::uint8_t Framer::ascii_delimiter() const {
    if (const auto* ascii = std::get_if<AsciiFramer>(&impl_)) return ascii->end_delimiter();
    return '\n';
}

}  // namespace mblab::protocol
