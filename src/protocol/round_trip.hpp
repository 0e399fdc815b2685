#pragma once

#include <cstdint>
#include <span>

// The codec's own consistency check, shared by the fuzz targets and the corpus replay test: a
// PDU the decoder accepts must encode back to exactly the same bytes, those must decode again,
// and the views it hands out (file record sub-requests, device id objects...) must walk to
// exactly their end.
namespace mblab::protocol {

enum class RoundTrip : std::uint8_t {
    Rejected,  // the decoder refused the PDU (a DecodeError): nothing to compare
    Same,      // decode -> encode -> decode gave back the input bytes
    Differs,   // a codec bug: encoding lost or changed something, refused its own output, or a
               // decoded view does not walk to its end
};

RoundTrip request_round_trip(std::span<const std::uint8_t> pdu);
RoundTrip response_round_trip(std::span<const std::uint8_t> pdu);

}  // namespace mblab::protocol
