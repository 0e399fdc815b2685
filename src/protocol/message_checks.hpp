#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>

#include "protocol/direction.hpp"
#include "protocol/field_reader.hpp"
#include "protocol/file_record.hpp"
#include "protocol/limits.hpp"
#include "protocol/request.hpp"
#include "protocol/shared_fields.hpp"
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
void check_diagnostic(FieldReader& reader, std::uint16_t sub, std::span<const std::uint8_t> data,
                      Direction direction);

// FC 2B / 0E read device id code 01..04, else 03.
void check_read_device_id_code(FieldReader& reader, std::uint8_t code);

// The alternative of a variant that is built on `Layout` (shared_fields.hpp).
template <class Layout, class Message, class... Rest>
constexpr auto built_on(std::type_identity<std::variant<Message, Rest...>>) {
    if constexpr (std::is_base_of_v<Layout, Message>) {
        return std::type_identity<Message>{};
    } else {
        return built_on<Layout>(std::type_identity<std::variant<Rest...>>{});
    }
}

// Decoders of the layouts that a request and its response share, for the side whose variant is
// `Variant`: the request and response decoders derive from it.
template <class Variant, Direction Way>
struct SharedDecoders {
    template <class Layout>
    using Message = typename decltype(built_on<Layout>(std::type_identity<Variant>{}))::type;

    static Result<Variant> write_single_coil(FieldReader& in) {  // 05
        Message<AddressValue<FunctionCode::WriteSingleCoil>> message;
        in.u16(message.address, "output address").u16(message.value, "output value").end();
        check_coil_value(in, message.value);
        return finish<Variant>(in, message);
    }
    static Result<Variant> write_single_register(FieldReader& in) {  // 06
        Message<AddressValue<FunctionCode::WriteSingleRegister>> message;
        in.u16(message.address, "register address").u16(message.value, "register value").end();
        return finish<Variant>(in, message);
    }
    static Result<Variant> diagnostics(FieldReader& in) {  // 08
        Message<DiagnosticsFields> message;
        in.u16(message.sub_function, "sub-function").rest(message.data);
        check_diagnostic(in, message.sub_function, message.data, Way);
        return finish<Variant>(in, message);
    }
    static Result<Variant> write_file_record(FieldReader& in) {  // 15
        Message<WriteFileRecordFields> message;
        write_file_record_body(in, message.sub_requests);
        return finish<Variant>(in, message);
    }
    // 2B with an MEI type other than 0E: `not_canopen` is the direction's error for one other
    // than 0D.
    static Result<Variant> canopen(FieldReader& in, std::uint8_t mei_type,
                                   const DecodeError& not_canopen) {
        in.require(mei_type == kMeiCanopen, not_canopen);
        Message<CanopenFields> message;
        message.mei_type = mei_type;
        in.rest(message.data);
        return finish<Variant>(in, message);
    }
    static Result<Variant> mask_write_register(FieldReader& in) {  // 16
        Message<MaskWriteFields> message;
        in.u16(message.address, "reference address")
            .u16(message.and_mask, "and mask")
            .u16(message.or_mask, "or mask")
            .end();
        return finish<Variant>(in, message);
    }
};

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
