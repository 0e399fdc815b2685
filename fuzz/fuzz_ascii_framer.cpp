#include <array>

#include "framer_fuzz.hpp"
#include "protocol/adu.hpp"

namespace {

using mblab::fuzz::require;
namespace protocol = mblab::protocol;

void check_frame(const protocol::FrameEvent& event) {
    const auto& adu = event.adu;
    require(adu.size() >= 9 && adu.size() <= 513, "ASCII frame size out of limits");
    require(adu.front() == ':' && adu[adu.size() - 2] == '\r' && adu.back() == '\n',
            "frame not delimited by ':' and CR LF");
    // Writing the decoded address and PDU again gives the same characters; this also checks
    // the LRC, which the writer computes afresh. A lenient framer's frame with a bad LRC, or in
    // lower-case hex (a framing error [SER 2.5.2] the writer never makes), differs, and must say
    // so.
    std::array<std::uint8_t, 513> again{};
    const std::size_t written = protocol::write_adu(event.header, event.pdu, again);
    require(written == adu.size(), "re-encoded frame has another size");
    bool same = true;
    for (std::size_t i = 0; i < written; ++i) {
        same = same && adu[i] == again[i];
    }
    require(mblab::fuzz::clean_or_excused(event, same), "re-encoded frame differs");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const char kGood[] = ":1103006B00037E\r\n";
    return mblab::fuzz::fuzz_framer(
        data, size, {.framing = protocol::Framing::Ascii}, check_frame, [](std::uint8_t) {
            return std::span(reinterpret_cast<const std::uint8_t*>(kGood), sizeof kGood - 1);
        });
}
