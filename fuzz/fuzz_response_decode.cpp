// Response PDU decoder (a client facing hostile servers): must never read out of bounds, and
// whatever it accepts must round-trip.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "protocol/round_trip.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> pdu(data, size);
    if (mblab::protocol::response_round_trip(pdu) == mblab::protocol::RoundTrip::Differs) {
        std::abort();
    }
    return 0;
}
