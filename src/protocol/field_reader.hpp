#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "protocol/cursor.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/result.hpp"

// Decoding support shared by the request and response codecs (not part of the public API).
namespace mblab::protocol::detail {

constexpr DecodeError value_error(const char* field, const char* reason) {
    return {ExceptionCode::IllegalDataValue, field, reason};
}
constexpr DecodeError address_error(const char* field, const char* reason) {
    return {ExceptionCode::IllegalDataAddress, field, reason};
}
constexpr DecodeError function_error(const char* field, const char* reason) {
    return {ExceptionCode::IllegalFunction, field, reason};
}

// What a count field may hold when it counts every byte after it.
struct CountRule {
    const char* field = "";
    std::size_t min = 0;
    std::size_t max = 0;
    std::size_t multiple_of = 1;
    const char* reason = "";  // the allowed range, as users read it
};

// Reads named wire fields in order and keeps the first failure, so a decoder reads as the
// field table of [APP] and checks as its state diagram: each step after a failure does nothing.
// A truncated field or bytes after the last field are exception 03 (the implied length is wrong).
class FieldReader {
  public:
    explicit FieldReader(std::span<const std::uint8_t> bytes) : cursor_(bytes) {}

    bool ok() const { return !failed_; }
    const DecodeError& error() const { return error_; }
    std::size_t remaining() const { return cursor_.remaining(); }

    FieldReader& u8(std::uint8_t& out, const char* field) {
        if (ok() && !cursor_.read_u8(out)) fail(value_error(field, kTruncated));
        return *this;
    }
    FieldReader& u16(std::uint16_t& out, const char* field) {
        if (ok() && !cursor_.read_u16(out)) fail(value_error(field, kTruncated));
        return *this;
    }
    FieldReader& bytes(std::size_t count, std::span<const std::uint8_t>& out, const char* field) {
        if (ok() && !cursor_.read_bytes(count, out)) fail(value_error(field, kTruncated));
        return *this;
    }
    // Everything left, for fields that run to the end of the PDU.
    FieldReader& rest(std::span<const std::uint8_t>& out) {
        if (ok()) cursor_.read_bytes(cursor_.remaining(), out);
        return *this;
    }
    FieldReader& end() {
        if (ok() && !cursor_.empty()) fail(value_error("PDU length", kTrailing));
        return *this;
    }
    // A counted field's count must equal the bytes that follow it in the PDU.
    FieldReader& counts_rest(std::size_t count, const char* field) {
        return require(count == remaining(), value_error(field, kCountMismatch));
    }
    // A one-byte count that follows `rule` and counts the rest of the PDU, then that rest.
    FieldReader& counted_rest(const CountRule& rule, std::span<const std::uint8_t>& out) {
        std::uint8_t count = 0;
        u8(count, rule.field);
        require(count >= rule.min && count <= rule.max && count % rule.multiple_of == 0,
                value_error(rule.field, rule.reason));
        return counts_rest(count, rule.field).rest(out);
    }
    FieldReader& require(bool condition, const DecodeError& error) {
        if (ok() && !condition) fail(error);
        return *this;
    }
    FieldReader& fail(const DecodeError& error) {
        if (ok()) {
            failed_ = true;
            error_ = error;
        }
        return *this;
    }

    static constexpr const char* kTruncated = "the PDU ends before this field";
    static constexpr const char* kTrailing = "bytes follow the last field of the PDU";
    static constexpr const char* kCountMismatch = "must equal the number of bytes that follow it";

  private:
    ReadCursor cursor_;
    bool failed_ = false;
    DecodeError error_;
};

// Wraps a decoded message into the Result of its variant, or passes the reader's error on.
template <class Variant, class Message>
Result<Variant> finish(const FieldReader& reader, const Message& message) {
    if (!reader.ok()) return reader.error();
    return Variant{message};
}

// Both directions: the size limits of any PDU, then the decoder of its function code.
template <class Variant>
Result<Variant> decode_pdu(std::span<const std::uint8_t> pdu,
                           Result<Variant> (*decode_body)(std::uint8_t code, FieldReader& in)) {
    if (pdu.empty()) return value_error("function code", "the PDU is empty");
    if (pdu.size() > limits::kMaxPdu) return value_error("PDU length", "must be 253 bytes or less");
    FieldReader in(pdu.subspan(1));
    return decode_body(pdu[0], in);
}

// A function code mblab has no type for: its bytes are carried as they are, so a device can
// answer 01 and a gateway or tester can pass them on.
template <class Variant, class Raw>
Result<Variant> decode_raw(std::uint8_t code, FieldReader& in) {
    Raw message;
    message.function = code;
    in.rest(message.data);
    return finish<Variant>(in, message);
}

}  // namespace mblab::protocol::detail
