#pragma once

#include <cstdint>

#include "protocol/field_reader.hpp"

// Validation of FC 2B / 0E responses (not part of the public API).
namespace mblab::protocol::detail {

struct ReadDeviceIdHeader {
    std::uint8_t read_code = 0;
    std::uint8_t conformity_level = 0;
    std::uint8_t more_follows = 0;
    std::uint8_t object_count = 0;
};

// Read code 01..04, conformity level 01..03 or 81..83, more follows 00 / FF (00 and a single
// object for individual access), and `objects` holds exactly `object_count` id / length / value
// triples.
void check_read_device_id_response(FieldReader& reader, const ReadDeviceIdHeader& header,
                                   std::span<const std::uint8_t> objects);

}  // namespace mblab::protocol::detail
