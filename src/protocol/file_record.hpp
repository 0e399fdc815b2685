#pragma once

#include <span>

#include "protocol/field_reader.hpp"

// Decoding of the FC 14 / 15 bodies: the byte count, then the sub-requests or sub-responses it
// counts, which become the views of the decoded message (not part of the public API).
namespace mblab::protocol::detail {

// FC 14 request: byte count 0x07..0xF5 in 7-byte sub-requests, each asking for 1 or more
// registers, all the answers fitting one response (03); then reference type 6, file 1..FFFF and
// records 0..9999 (02, [APP] figure 24).
void read_file_record_request_body(FieldReader& reader, std::span<const std::uint8_t>& subs);

// FC 15 request and its echo: byte count 0x09..0xFB; each sub-request's header and record data
// lie inside it and carry 1 or more registers (03); then the same reference checks as FC 14 (02).
void write_file_record_body(FieldReader& reader, std::span<const std::uint8_t>& subs);

// FC 14 response: sub-responses (length, reference type 6, registers) tile the data exactly.
void read_file_record_response_body(FieldReader& reader, std::span<const std::uint8_t>& subs);

}  // namespace mblab::protocol::detail
