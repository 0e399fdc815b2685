#include "protocol/message_checks.hpp"

#include "protocol/function_code.hpp"

namespace mblab::protocol::detail {

namespace {

constexpr std::uint32_t kAddressSpace = 0x10000;
constexpr std::uint16_t kCoilOn = 0xFF00;
constexpr std::uint16_t kCoilOff = 0x0000;

std::uint16_t data_word(std::span<const std::uint8_t> data) {
    return static_cast<std::uint16_t>(data[0] << 8 | data[1]);
}

// The value [APP] 6.8.1 allows in the data field of a sub-function other than 00.
bool diagnostic_value_allowed(std::uint16_t sub, std::uint16_t value) {
    switch (static_cast<DiagnosticSub>(sub)) {
        case DiagnosticSub::RestartCommunications:
            return value == 0x0000 || value == 0xFF00;  // FF00 also clears the event log
        case DiagnosticSub::ChangeAsciiDelimiter:
            return (value & 0x00FF) == 0;  // CHAR 00
        default:
            return value == 0x0000;
    }
}

}  // namespace

void check_quantity(FieldReader& reader, std::uint16_t quantity, const QuantityLimit& limit) {
    reader.require(quantity >= 1 && quantity <= limit.max, value_error(limit.field, limit.reason));
}

void check_address_span(FieldReader& reader, std::uint16_t address, std::uint16_t quantity,
                        const char* field) {
    reader.require(std::uint32_t{address} + quantity <= kAddressSpace,
                   address_error(field, "address + quantity runs past 0xFFFF"));
}

void check_coil_value(FieldReader& reader, std::uint16_t value) {
    reader.require(value == kCoilOn || value == kCoilOff,
                   value_error("output value", "must be 0x0000 (off) or 0xFF00 (on)"));
}

void check_diagnostic(FieldReader& reader, std::uint16_t sub, std::span<const std::uint8_t> data,
                      Direction direction) {
    reader.require(is_known_diagnostic_sub(sub),
                   function_error("sub-function", "must be 00..04, 0A..12 or 14 ([APP] 6.8.1)"));
    if (sub == static_cast<std::uint16_t>(DiagnosticSub::ReturnQueryData)) return;
    reader.require(data.size() == 2,
                   value_error("data", "must be 2 bytes for sub-functions other than 00"));
    if (!reader.ok()) return;
    if (direction == Direction::Request || diagnostic_answer_echoes(sub)) {
        reader.require(diagnostic_value_allowed(sub, data_word(data)),
                       value_error("data", "must be 0000 (01: 0000 or FF00; 03: CHAR 00)"));
    }
}

void check_read_device_id_code(FieldReader& reader, std::uint8_t code) {
    reader.require(code >= limits::kMinReadDeviceIdCode && code <= limits::kMaxReadDeviceIdCode,
                   value_error("read device id code", "must be 01..04"));
}

}  // namespace mblab::protocol::detail
