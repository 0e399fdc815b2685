#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "protocol/field_reader.hpp"
#include "protocol/limits.hpp"
#include "protocol/request.hpp"
#include "support/hex_digits.hpp"

// Checks that requests and their echoing responses share (not part of the public API).
namespace mblab::protocol::detail {

struct QuantityLimit {
    std::uint16_t max = 0;
    const char* field = "";
    const char* reason = "";
};

// "must be 1..125 (0x0001..0x007D)", spelled from the limit so that the two cannot disagree.
template <std::uint16_t Max>
struct QuantityReason {
    std::array<char, 34> text{};  // room for "must be 1..65535 (0x0001..0xFFFF)" and a NUL

    constexpr QuantityReason() {
        std::size_t at = 0;
        const auto put = [&](std::string_view part) {
            for (const char c : part)
                text[at++] = c;
        };
        put("must be 1..");
        std::array<char, 5> decimal{};
        std::size_t digits = 0;
        for (std::uint16_t rest = Max; rest != 0 || digits == 0; rest /= 10)
            decimal[digits++] = static_cast<char>('0' + rest % 10);
        while (digits > 0)
            text[at++] = decimal[--digits];
        put(" (0x0001..0x");
        for (int shift = 12; shift >= 0; shift -= 4)
            text[at++] = kHexDigits[(Max >> shift) & 0xF];
        put(")");
    }
};

template <std::uint16_t Max>
inline constexpr QuantityReason<Max> kQuantityReason{};

template <std::uint16_t Max>
constexpr QuantityLimit quantity_limit(const char* field) {
    return {Max, field, kQuantityReason<Max>.text.data()};
}

inline constexpr QuantityLimit kReadBitsLimit = quantity_limit<limits::kMaxReadBits>("quantity");
inline constexpr QuantityLimit kReadRegistersLimit =
    quantity_limit<limits::kMaxReadRegisters>("quantity");
inline constexpr QuantityLimit kWriteCoilsLimit =
    quantity_limit<limits::kMaxWriteCoils>("quantity");
inline constexpr QuantityLimit kWriteRegistersLimit =
    quantity_limit<limits::kMaxWriteRegisters>("quantity");
inline constexpr QuantityLimit kReadWriteReadLimit =
    quantity_limit<limits::kMaxReadWriteRead>("quantity to read");
inline constexpr QuantityLimit kReadWriteWriteLimit =
    quantity_limit<limits::kMaxReadWriteWrite>("quantity to write");

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
