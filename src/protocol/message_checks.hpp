#pragma once

#include <cstdint>
#include <span>

#include "protocol/field_reader.hpp"
#include "protocol/limits.hpp"
#include "protocol/request.hpp"

// Checks that requests and their echoing responses share (not part of the public API).
namespace mblab::protocol::detail {

struct QuantityLimit {
    std::uint16_t max = 0;
    const char* field = "";
    const char* reason = "";
};

inline constexpr QuantityLimit kReadBitsLimit{limits::kMaxReadBits, "quantity",
                                              "must be 1..2000 (0x0001..0x07D0)"};
inline constexpr QuantityLimit kReadRegistersLimit{limits::kMaxReadRegisters, "quantity",
                                                   "must be 1..125 (0x0001..0x007D)"};
inline constexpr QuantityLimit kWriteCoilsLimit{limits::kMaxWriteCoils, "quantity",
                                                "must be 1..1968 (0x0001..0x07B0)"};
inline constexpr QuantityLimit kWriteRegistersLimit{limits::kMaxWriteRegisters, "quantity",
                                                    "must be 1..123 (0x0001..0x007B)"};
inline constexpr QuantityLimit kReadWriteReadLimit{limits::kMaxReadWriteRead, "quantity to read",
                                                   "must be 1..125 (0x0001..0x007D)"};
inline constexpr QuantityLimit kReadWriteWriteLimit{limits::kMaxReadWriteWrite, "quantity to write",
                                                    "must be 1..121 (0x0001..0x0079)"};

// Bytes that `count` packed bits take on the wire.
constexpr std::size_t packed_size(std::size_t count) {
    return (count + 7) / 8;
}

// Quantity outside 1..max is exception 03.
void check_quantity(FieldReader& reader, std::uint16_t quantity, const QuantityLimit& limit);
// A range running past address 0xFFFF is exception 02: no map holds it.
void check_address_span(FieldReader& reader, std::uint16_t address, std::uint16_t quantity,
                        const char* field);

// FC 05 output value: 0x0000 or 0xFF00, else 03.
void check_coil_value(FieldReader& reader, std::uint16_t value);

// FC 08: an unknown sub-function is 01 ([APP] figure 18); sub-function 00 echoes any data, the
// others carry one 2-byte field. A request's field must hold the value [APP] 6.8.1 lists; a
// response's field is checked only where the response echoes the request.
enum class Direction : std::uint8_t { Request, Response };
void check_diagnostic(FieldReader& reader, std::uint16_t sub, std::span<const std::uint8_t> data,
                      Direction direction);

// FC 2B / 0E read device id code 01..04, else 03.
void check_read_device_id_code(FieldReader& reader, std::uint8_t code);

// Messages whose response echoes the request field for field: one reader serves both.
template <class Message>  // 05
void read_write_single_coil(FieldReader& reader, Message& message) {
    reader.u16(message.address, "output address").u16(message.value, "output value").end();
    check_coil_value(reader, message.value);
}
template <class Message>  // 06
void read_write_single_register(FieldReader& reader, Message& message) {
    reader.u16(message.address, "register address").u16(message.value, "register value").end();
}
template <class Message>  // 16
void read_mask_write_register(FieldReader& reader, Message& message) {
    reader.u16(message.address, "reference address")
        .u16(message.and_mask, "and mask")
        .u16(message.or_mask, "or mask")
        .end();
}

// Decodes a message whose fields `read` reads, into either variant.
template <class Variant, class Message>
Result<Variant> decode_fixed(FieldReader& reader, void (*read)(FieldReader&, Message&)) {
    Message message;
    read(reader, message);
    return finish<Variant>(reader, message);
}

// FC 5B, request or response: the fragment byte count counts every byte after it (CTP
// 7.13.1.4) and must cover at least the fields both directions carry.
inline void read_object_messaging_header(FieldReader& reader, ObjectMessagingHeader& message,
                                         std::size_t min_fragment, const char* reason) {
    reader.u8(message.fragment_byte_count, "fragment byte count")
        .counts_rest(message.fragment_byte_count, "fragment byte count")
        .require(message.fragment_byte_count >= min_fragment,
                 value_error("fragment byte count", reason))
        .u8(message.fragment_protocol, "fragment protocol")
        .u16(message.class_id, "class id")
        .u16(message.instance_id, "instance id")
        .u16(message.service_code, "service code");
}

}  // namespace mblab::protocol::detail
