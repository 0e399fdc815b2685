#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/direction.hpp"

namespace mblab::protocol {

// How long an RTU frame is, judged from its first bytes.
struct RtuFrameLength {
    enum class Kind : std::uint8_t {
        Known,      // `bytes` is the whole ADU: address, PDU, CRC (may exceed 256 if malformed)
        NeedBytes,  // look again once `bytes` bytes are held
        Unknown,    // the layout does not say; only silence (t3.5) ends the frame
    };
    Kind kind = Kind::NeedBytes;
    std::size_t bytes = 0;

    friend bool operator==(const RtuFrameLength&, const RtuFrameLength&) = default;
};

// Frame length from the request or response layout in the function code's row of kFunctionTable
// (function_table.hpp): a fixed size, or a byte count at an offset. Exception responses are 5
// bytes. Unknown: unknown function codes, FC 08 sub-function 00 (echo of any length) and
// sub-functions mblab does not know, FC 2B with a MEI type other than 0x0E. FC 2B/0E responses are
// measured by walking their objects. `head` is the frame so far, address first.
RtuFrameLength rtu_frame_length(Direction direction, std::span<const std::uint8_t> head);

}  // namespace mblab::protocol
