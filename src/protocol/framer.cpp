#include "protocol/framer.hpp"

namespace mblab::protocol {

namespace {

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

bool Framer::has_partial() const {
    return std::visit([](const auto& framer) { return framer.has_partial(); }, impl_);
}

std::optional<MbapHeader> Framer::partial_header() const {
    if (const auto* mbap = std::get_if<MbapFramer>(&impl_)) return mbap->partial_header();
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
