#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "protocol/limits.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"
#include "support/hex.hpp"

// Helpers for the PDU codec tests.
namespace mblab::protocol::testing {

// Encodes into a PDU-sized buffer; a refused encode fails the test and gives no bytes.
template <class Message>
std::vector<std::uint8_t> encoded_with(const Message& message,
                                       bool (*encode)(const Message&, WriteCursor&)) {
    std::array<std::uint8_t, limits::kMaxPdu> buffer{};
    WriteCursor out(buffer);
    const bool ok = encode(message, out);
    EXPECT_TRUE(ok) << "encoder refused the message";
    if (!ok) return {};
    const auto written = out.written();
    return {written.begin(), written.end()};
}
inline std::vector<std::uint8_t> encoded(const Request& request) {
    return encoded_with(request, encode_request);
}
inline std::vector<std::uint8_t> encoded(const Response& response) {
    return encoded_with(response, encode_response);
}

// "56 32 2E 31 31" for "V2.11": device id strings inside hex vectors.
inline std::string ascii_hex(std::string_view text) {
    const std::vector<std::uint8_t> bytes(text.begin(), text.end());
    return " " + mblab::test::to_hex(bytes) + " ";
}

// "41 41 41 ..." : `count` copies of one byte, for vectors at a length limit.
inline std::string repeat_hex(std::string_view byte, std::size_t count) {
    std::string out;
    for (std::size_t i = 0; i < count; ++i)
        (out += ' ') += byte;
    return out + ' ';
}

// One row of a parameterised PDU table. Rows of accepted PDUs leave `field` empty.
struct PduCase {
    PduCase(std::string name_, std::string pdu_, std::string field_ = "",
            ExceptionCode exception_ = ExceptionCode::IllegalDataValue)
        : name(std::move(name_)),
          pdu(std::move(pdu_)),
          field(std::move(field_)),
          exception(exception_) {}

    std::string name;
    std::string pdu;
    std::string field;        // the wire field a refusal names
    ExceptionCode exception;  // the answer a server gives to a refused request
};

inline std::ostream& operator<<(std::ostream& out, const PduCase& row) {
    return out << row.name << " [" << row.pdu << "]";
}

inline std::string case_name(const ::testing::TestParamInfo<PduCase>& info) {
    return info.param.name;
}

// Decodes `pdu`, then re-encodes the message: the bytes must come back unchanged.
template <class Message>
void expect_round_trip(const std::string& pdu_hex,
                       Result<Message> (*decode)(std::span<const std::uint8_t>)) {
    const auto pdu = mblab::test::hex(pdu_hex);
    const auto decoded = decode(pdu);
    ASSERT_TRUE(decoded.ok()) << decoded.error().field << ": " << decoded.error().reason;
    EXPECT_EQ(function_of(*decoded), pdu[0]);
    EXPECT_EQ(mblab::test::to_hex(encoded(*decoded)), mblab::test::to_hex(pdu));
}

// Decodes `pdu_hex`, which must be refused naming `field`; returns the error for more checks.
template <class Message>
DecodeError expect_refused(const std::string& pdu_hex, const std::string& field,
                           Result<Message> (*decode)(std::span<const std::uint8_t>)) {
    const auto decoded = decode(mblab::test::hex(pdu_hex));
    if (decoded.ok()) {
        ADD_FAILURE() << "decoded a PDU that must be refused";
        return {};
    }
    EXPECT_EQ(decoded.error().field, field);
    EXPECT_NE(std::string(decoded.error().reason), "");
    return decoded.error();
}

// Decodes `pdu` as one message type. The result views `pdu`: keep the vector alive.
template <class Message, class Variant>
Message decoded_as(const std::vector<std::uint8_t>& pdu,
                   Result<Variant> (*decode)(std::span<const std::uint8_t>)) {
    const auto result = decode(pdu);
    if (!result.ok()) {
        ADD_FAILURE() << result.error().field << ": " << result.error().reason;
        return {};
    }
    const auto* message = std::get_if<Message>(&*result);
    if (message == nullptr) {
        ADD_FAILURE() << "decoded to another message type (index " << result->index() << ")";
        return {};
    }
    return *message;
}

}  // namespace mblab::protocol::testing
