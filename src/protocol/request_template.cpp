#include "protocol/request_template.hpp"

#include "protocol/function_table.hpp"
#include "protocol/limits.hpp"
#include "support/hex_digits.hpp"

namespace mblab::protocol {

namespace {

constexpr ExceptionCode k02 = ExceptionCode::IllegalDataAddress;

constexpr RequestField address(std::string_view name, std::uint8_t offset = 1) {
    return {name, offset, 2, FieldRole::Address};
}
constexpr RequestField quantity(std::string_view name, std::uint16_t max, std::uint8_t offset = 3,
                                FieldRole role = FieldRole::Quantity) {
    return {name, offset, 2, role, FieldRule::Range, 1, max};
}
constexpr RequestField word(std::string_view name, std::uint8_t offset) {
    return {name, offset, 2};
}
constexpr RequestField byte_count(std::string_view name, std::uint8_t offset, FieldRule rule,
                                  std::size_t min = 0, std::size_t max = 0xFF) {
    return {name,
            offset,
            1,
            FieldRole::ByteCount,
            rule,
            static_cast<std::uint16_t>(min),
            static_cast<std::uint16_t>(max)};
}

constexpr AnswerField kByteCount{"byte count", 1, 1};

// FC 14 / 15: a byte count of min..max, then the first sub-request: reference type, file,
// record, length. A reference outside type 6, file 1..0xFFFF, record 0..9999 is 02 ([APP]
// figures 24 and 25).
constexpr RequestTemplate file_record(FunctionCode code, std::string_view count, std::uint8_t min,
                                      std::uint8_t max, std::string_view sample,
                                      std::string_view harmless) {
    return {.code = code,
            .table = DataTable::FileRecords,
            .fields = {byte_count(count, 1, FieldRule::CountsRest, min, max),
                       {"reference type", 2, 1, FieldRole::Other, FieldRule::Range,
                        limits::kFileRecordReferenceType, limits::kFileRecordReferenceType, k02},
                       {"file number", 3, 2, FieldRole::Other, FieldRule::Range, 1, 0xFFFF, k02},
                       {"record number", 5, 2, FieldRole::Other, FieldRule::Range, 0,
                        limits::kMaxFileRecordNumber, k02},
                       word("record length", 7)},
            .sample = sample,
            .harmless = harmless,
            .answer = {kByteCount}};
}

// FC 01..04: starting address and a quantity up to `max`; the answer a byte count and values.
constexpr RequestTemplate read_range(FunctionCode code, DataTable table, std::string_view name,
                                     std::uint16_t max, std::string_view sample,
                                     std::string_view values) {
    return {.code = code,
            .table = table,
            .fields = {address("starting address"), quantity(name, max)},
            .sample = sample,
            .answer = {kByteCount},
            .answer_rest = values};
}

// FC 07, 0B, 0C, 11: the function code is the whole request.
constexpr RequestTemplate bare(FunctionCode code, std::string_view sample,
                               FixedList<AnswerField, 6> answer) {
    return {.code = code, .sample = sample, .answer = answer};
}

constexpr AnswerField kAddress{"address", 1, 2};

// FC 05, 06: an address and the value written there, which the answer echoes.
constexpr RequestTemplate single_write(FunctionCode code, DataTable table,
                                       FixedList<RequestField, 5> fields, std::string_view sample,
                                       std::string_view harmless, ValueForm form) {
    return {.code = code,
            .table = table,
            .fields = fields,
            .sample = sample,
            .harmless = harmless,
            .value_form = form,
            .value_at = 3,
            .answer = {kAddress, {"value", 3, 2}}};
}

// FC 0F, 10: starting address, a quantity up to `max`, its byte count by `count`, the values;
// the answer echoes address and quantity. The harmless request asks for a quantity of 0.
constexpr RequestTemplate multiple_write(FunctionCode code, DataTable table, std::string_view name,
                                         std::uint16_t max, FieldRule count,
                                         std::string_view sample, std::string_view harmless,
                                         ValueForm form) {
    return {.code = code,
            .table = table,
            .fields = {address("starting address"), quantity(name, max),
                       byte_count("byte count", 5, count)},
            .sample = sample,
            .harmless = harmless,
            .value_form = form,
            .value_at = 6,
            .answer = {{"starting address", 1, 2}, {"quantity", 3, 2}}};
}

// Limits: [APP] section 6, by the section cited above each row.
constexpr RequestTemplate kTemplates[] = {
    // 6.1, 6.2: quantity of coils or inputs 1..2000 (0x07D0).
    read_range(FunctionCode::ReadCoils, DataTable::Coils, "quantity of coils", limits::kMaxReadBits,
               "01 0000 0001", "bit values"),
    read_range(FunctionCode::ReadDiscreteInputs, DataTable::DiscreteInputs, "quantity of inputs",
               limits::kMaxReadBits, "02 0000 0001", "bit values"),
    // 6.3, 6.4: quantity of registers 1..125 (0x007D).
    read_range(FunctionCode::ReadHoldingRegisters, DataTable::HoldingRegisters,
               "quantity of registers", limits::kMaxReadRegisters, "03 0000 0001",
               "register values"),
    read_range(FunctionCode::ReadInputRegisters, DataTable::InputRegisters,
               "quantity of input registers", limits::kMaxReadRegisters, "04 0000 0001",
               "register values"),
    // 6.5: output value 0x0000 or 0xFF00; 0x1234 is neither.
    single_write(
        FunctionCode::WriteSingleCoil, DataTable::Coils,
        {address("output address"), {"output value", 3, 2, FieldRole::Other, FieldRule::CoilValue}},
        "05 0000 0000", "05 0000 1234", ValueForm::CoilWord),
    // 6.6; the harmless request lacks its value.
    single_write(FunctionCode::WriteSingleRegister, DataTable::HoldingRegisters,
                 {address("register address"), word("register value", 3)}, "06 0000 0000",
                 "06 0000", ValueForm::Word),
    // 6.7: the answer is one byte of output data.
    bare(FunctionCode::ReadExceptionStatus, "07", {{"output data", 1, 1}}),
    // 6.8: sub-function 00 (return query data) echoes its data.
    {.code = FunctionCode::Diagnostics,
     .fields = {word("sub-function", 1), word("data", 3)},
     .sample = "08 0000 1234",
     .answer = {{"sub-function", 1, 2}}},
    // 6.9: the answer is a status word and an event count; 6.10.
    bare(FunctionCode::GetCommEventCounter, "0B", {{"status", 1, 2}, {"event count", 3, 2}}),
    bare(FunctionCode::GetCommEventLog, "0C", {kByteCount}),
    // 6.11: quantity of outputs 1..1968 (0x07B0), byte count = quantity / 8 rounded up.
    multiple_write(FunctionCode::WriteMultipleCoils, DataTable::Coils, "quantity of outputs",
                   limits::kMaxWriteCoils, FieldRule::BitBytes, "0F 0000 0001 01 00",
                   "0F 0000 0000 00", ValueForm::PackedBits),
    // 6.12: quantity of registers 1..123 (0x007B), byte count 2 x quantity.
    multiple_write(FunctionCode::WriteMultipleRegisters, DataTable::HoldingRegisters,
                   "quantity of registers", limits::kMaxWriteRegisters, FieldRule::RegisterBytes,
                   "10 0000 0001 02 0000", "10 0000 0000 00", ValueForm::Word),
    // 6.13.
    bare(FunctionCode::ReportServerId, "11", {kByteCount}),
    // 6.14: byte count 0x07..0xF5, 7 bytes a sub-request; file 1, record 0, one register.
    file_record(FunctionCode::ReadFileRecord, "byte count", limits::kMinFileRecordByteCount,
                limits::kMaxFileRecordByteCount, "14 07 06 0001 0000 0001", {}),
    // 6.15: request data length 0x09..0xFB (limits.hpp says why not 0x07..0xF5).
    file_record(FunctionCode::WriteFileRecord, "request data length",
                limits::kMinWriteFileRecordByteCount, limits::kMaxWriteFileRecordByteCount,
                "15 09 06 0001 0000 0001 0000", "15 00"),
    // 6.16: AND 0xFFFF, OR 0x0000 keeps the register as it is.
    {.code = FunctionCode::MaskWriteRegister,
     .table = DataTable::HoldingRegisters,
     .fields = {address("reference address"), word("and mask", 3), word("or mask", 5)},
     .sample = "16 0000 FFFF 0000",
     .answer = {kAddress, {"AND mask", 3, 2}, {"OR mask", 5, 2}}},
    // 6.17: quantity to read 1..125 (0x007D), to write 1..121 (0x0079), write byte count 2 x
    // quantity to write; the harmless request writes none.
    {.code = FunctionCode::ReadWriteMultipleRegisters,
     .table = DataTable::HoldingRegisters,
     .fields = {{"read starting address", 1, 2, FieldRole::ReadAddress},
                quantity("quantity to read", limits::kMaxReadWriteRead, 3, FieldRole::ReadQuantity),
                address("write starting address", 5),
                quantity("quantity to write", limits::kMaxReadWriteWrite, 7),
                byte_count("write byte count", 9, FieldRule::RegisterBytes)},
     .sample = "17 0000 0001 0000 0001 02 0000",
     .harmless = "17 0000 0001 0000 0000 00",
     .value_form = ValueForm::Word,
     .value_at = 10,
     .answer = {kByteCount},
     .answer_rest = "register values"},
    // 6.18: the answer's byte count takes two bytes.
    {.code = FunctionCode::ReadFifoQueue,
     .table = DataTable::HoldingRegisters,
     .fields = {address("FIFO pointer address")},
     .sample = "18 0000",
     .answer = {{"byte count", 1, 2}, {"FIFO count", 3, 2}},
     .answer_rest = "FIFO values"},
    // 6.21: read device id code 01..04; basic identification as a stream from object 0. A MEI
    // type other than 0x0D / 0x0E is 01 (annex A), not a value error.
    {.code = FunctionCode::EncapsulatedInterface,
     .fields = {{"MEI type", 1, 1},
                {"read device id code", 2, 1, FieldRole::Other, FieldRule::Range,
                 limits::kMinReadDeviceIdCode, limits::kMaxReadDeviceIdCode},
                {"object id", 3, 1}},
     .sample = "2B 0E 01 00",
     .answer = {{"MEI type", 1, 1},
                {"read device id code", 2, 1},
                {"conformity level", 3, 1},
                {"more follows", 4, 1},
                {"next object id", 5, 1},
                {"number of objects", 6, 1}},
     .answer_rest = "objects"},
    // CTP 7.13.1.4: the fragment byte count counts every byte after it, 7 or more, up to what a
    // PDU holds. Class, instance and service are the device's own: no request is plain to all.
    {.code = FunctionCode::ObjectMessaging,
     .fields = {byte_count("fragment byte count", 1, FieldRule::CountsRest,
                           limits::kMinObjectMessagingRequestFragment, limits::kMaxPdu - 2),
                {"fragment protocol", 2, 1},
                word("class id", 3),
                word("instance id", 5),
                word("service code", 7)},
     .answer = {kByteCount}},
};

constexpr bool same_rows_as_function_table() {
    if (std::size(kTemplates) != std::size(kFunctionTable)) return false;
    for (std::size_t i = 0; i < std::size(kFunctionTable); ++i) {
        if (kTemplates[i].code != kFunctionTable[i].code) return false;
    }
    return true;
}
static_assert(same_rows_as_function_table(), "one template per function row, in the same order");

// Uppercase hex, spaces anywhere between digits.
std::optional<std::vector<std::uint8_t>> bytes_of_hex(std::string_view text) {
    if (text.empty()) return std::nullopt;
    std::vector<std::uint8_t> out;
    int high = -1;
    for (char c : text) {
        if (c == ' ') continue;
        if (high < 0) {
            high = upper_hex_value(c);
        } else {
            out.push_back(static_cast<std::uint8_t>(high * 16 + upper_hex_value(c)));
            high = -1;
        }
    }
    return out;
}

// The first byte of such text, or -1 when it is not well-formed.
constexpr int first_byte_of_hex(std::string_view text) {
    int digits = 0;
    int first = 0;
    for (char c : text) {
        if (c == ' ') continue;
        const int value = upper_hex_value(c);
        if (value < 0) return -1;
        if (digits++ < 2) first = first * 16 + value;
    }
    return digits == 0 || digits % 2 != 0 ? -1 : first;
}

constexpr bool samples_start_with_their_code() {
    for (const RequestTemplate& row : kTemplates) {
        const int code = static_cast<int>(row.code);
        if (!row.sample.empty() && first_byte_of_hex(row.sample) != code) return false;
        if (!row.harmless.empty() && first_byte_of_hex(row.harmless) != code) return false;
    }
    return true;
}
static_assert(samples_start_with_their_code(), "uppercase hex, function code first");

}  // namespace

std::span<const RequestTemplate> request_templates() {
    return kTemplates;
}

const RequestTemplate* find_template(std::uint8_t code) {
    const std::uint8_t row = detail::kRowIndex[code];
    return row == detail::kNoRow ? nullptr : &kTemplates[row];
}

const RequestField* field_with(const RequestTemplate& request, FieldRole role) {
    for (const RequestField& field : request.fields) {
        if (field.role == role) return &field;
    }
    return nullptr;
}

std::optional<std::uint16_t> read_field(std::span<const std::uint8_t> pdu,
                                        const RequestField& field) {
    if (pdu.size() < std::size_t{field.offset} + field.width) return std::nullopt;
    if (field.width == 1) return pdu[field.offset];
    return static_cast<std::uint16_t>(pdu[field.offset] << 8 | pdu[field.offset + 1]);
}

void write_field(std::span<std::uint8_t> pdu, const RequestField& field, std::uint16_t value) {
    if (field.width == 1) {
        pdu[field.offset] = static_cast<std::uint8_t>(value);
        return;
    }
    pdu[field.offset] = static_cast<std::uint8_t>(value >> 8);
    pdu[field.offset + 1] = static_cast<std::uint8_t>(value);
}

std::optional<std::vector<std::uint8_t>> sample_request(std::uint8_t code) {
    const RequestTemplate* request = find_template(code);
    if (request == nullptr) return std::nullopt;
    return bytes_of_hex(request->sample);
}

std::optional<std::vector<std::uint8_t>> harmless_request(std::uint8_t code) {
    const RequestTemplate* request = find_template(code);
    if (request == nullptr) return std::nullopt;
    return bytes_of_hex(request->harmless.empty() ? request->sample : request->harmless);
}

bool writes(std::uint8_t code) {
    const FunctionRow* row = find_function(code);
    return row != nullptr && row->writes == Writes::Yes;
}

}  // namespace mblab::protocol
