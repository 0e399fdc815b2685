// The request templates against [APP] section 6, row by row: each sample is the request the spec's
// layout gives, each harmless request is one the parser refuses with 03, and each limit is one the
// parser accepts while one past it gets the field's exception.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "protocol/function_table.hpp"
#include "protocol/request.hpp"
#include "protocol/request_template.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using test::to_hex;
constexpr auto k02 = ExceptionCode::IllegalDataAddress;
constexpr auto k03 = ExceptionCode::IllegalDataValue;

struct Sample {
    std::uint8_t code;
    const char* sample;    // "" where the row has none
    const char* harmless;  // "" where the sample itself changes nothing
};

// Written out here from [APP] 6 so that a slip in the table shows.
constexpr Sample kSamples[] = {
    {0x01, "01 00 00 00 01", ""},
    {0x02, "02 00 00 00 01", ""},
    {0x03, "03 00 00 00 01", ""},
    {0x04, "04 00 00 00 01", ""},
    {0x05, "05 00 00 00 00", "05 00 00 12 34"},
    {0x06, "06 00 00 00 00", "06 00 00"},
    {0x07, "07", ""},
    {0x08, "08 00 00 12 34", ""},
    {0x0B, "0B", ""},
    {0x0C, "0C", ""},
    {0x0F, "0F 00 00 00 01 01 00", "0F 00 00 00 00 00"},
    {0x10, "10 00 00 00 01 02 00 00", "10 00 00 00 00 00"},
    {0x11, "11", ""},
    {0x14, "14 07 06 00 01 00 00 00 01", ""},
    {0x15, "15 09 06 00 01 00 00 00 01 00 00", "15 00"},
    {0x16, "16 00 00 FF FF 00 00", ""},
    {0x17, "17 00 00 00 01 00 00 00 01 02 00 00", "17 00 00 00 01 00 00 00 00 00"},
    {0x18, "18 00 00", ""},
    {0x2B, "2B 0E 01 00", ""},
    {0x5B, "", ""},
};

struct SpecLimit {
    std::uint8_t code;
    const char* field;
    std::uint16_t min;
    std::uint16_t max;
    ExceptionCode refusal;
};

// Every field [APP] bounds, with its section's numbers (CTP 7.13.1.4 for FC 5B).
constexpr SpecLimit kSpecLimits[] = {
    {0x01, "quantity of coils", 1, 0x07D0, k03},            // 6.1
    {0x02, "quantity of inputs", 1, 0x07D0, k03},           // 6.2
    {0x03, "quantity of registers", 1, 0x007D, k03},        // 6.3
    {0x04, "quantity of input registers", 1, 0x007D, k03},  // 6.4
    {0x0F, "quantity of outputs", 1, 0x07B0, k03},          // 6.11
    {0x10, "quantity of registers", 1, 0x007B, k03},        // 6.12
    {0x14, "byte count", 0x07, 0xF5, k03},                  // 6.14
    {0x14, "reference type", 6, 6, k02},                    // 6.14, figure 24
    {0x14, "file number", 1, 0xFFFF, k02},                  // 6.14
    {0x14, "record number", 0, 0x270F, k02},                // 6.14
    {0x15, "request data length", 0x09, 0xFB, k03},         // 6.15
    {0x15, "reference type", 6, 6, k02},                    // 6.15, figure 25
    {0x15, "file number", 1, 0xFFFF, k02},                  // 6.15
    {0x15, "record number", 0, 0x270F, k02},                // 6.15
    {0x17, "quantity to read", 1, 0x007D, k03},             // 6.17
    {0x17, "quantity to write", 1, 0x0079, k03},            // 6.17
    {0x2B, "read device id code", 1, 4, k03},               // 6.21
    {0x5B, "fragment byte count", 7, 251, k03},             // as much as a PDU holds
};

bool is_bounded(const RequestField& field) {
    return field.rule == FieldRule::Range || field.rule == FieldRule::CountsRest;
}

// The request the limits are tried on: the sample, or for FC 5B an empty service call.
std::vector<std::uint8_t> base_of(const RequestTemplate& row) {
    if (auto sample = sample_request(static_cast<std::uint8_t>(row.code))) return *sample;
    return hex("5B 07 00 00 01 00 01 00 07");
}

// `pdu` with the counted field at `value` and as many bytes after it: file record sub-requests
// repeated (FC 14), one sub-request whose record length fills the rest (FC 15), else zeros.
std::vector<std::uint8_t> with_count(std::vector<std::uint8_t> pdu, const RequestTemplate& row,
                                     const RequestField& field, std::uint16_t value) {
    const std::size_t body_at = field.offset + 1u;
    const std::vector<std::uint8_t> body(pdu.begin() + static_cast<long>(body_at), pdu.end());
    pdu[field.offset] = static_cast<std::uint8_t>(value);
    pdu.resize(body_at);
    if (row.code == FunctionCode::ReadFileRecord) {
        while (pdu.size() < body_at + value)
            pdu.insert(pdu.end(), body.begin(), body.begin() + 7);
    } else {
        pdu.insert(pdu.end(), body.begin(), body.end());
        if (row.code == FunctionCode::WriteFileRecord && value >= 7) {
            const auto registers = static_cast<std::uint16_t>((value - 7) / 2);
            write_field(pdu, RequestField{"record length", 7, 2}, registers);
        }
    }
    pdu.resize(body_at + value, 0x00);
    return pdu;
}

// `pdu` with `field` at `value`, byte counts that follow a quantity recomputed with their data.
std::vector<std::uint8_t> with_value(const RequestTemplate& row, const RequestField& field,
                                     std::uint16_t value) {
    std::vector<std::uint8_t> pdu = base_of(row);
    if (field.rule == FieldRule::CountsRest) return with_count(pdu, row, field, value);
    write_field(pdu, field, value);
    for (std::size_t i = 1; i < row.fields.size; ++i) {
        const RequestField& count = row.fields.items[i];
        if (count.rule != FieldRule::BitBytes && count.rule != FieldRule::RegisterBytes) continue;
        const std::size_t quantity = *read_field(pdu, row.fields.items[i - 1]);
        const std::size_t bytes =
            count.rule == FieldRule::BitBytes ? (quantity + 7) / 8 : 2 * quantity;
        pdu[count.offset] = static_cast<std::uint8_t>(bytes);
        pdu.resize(count.offset + 1 + bytes, 0x00);
    }
    return pdu;
}

void expect_accepted(const std::vector<std::uint8_t>& pdu) {
    const auto decoded = decode_request(pdu);
    EXPECT_TRUE(decoded) << to_hex(pdu) << ": " << (decoded ? "" : decoded.error().reason);
}

void expect_refused(const std::vector<std::uint8_t>& pdu, ExceptionCode refusal) {
    const auto decoded = decode_request(pdu);
    ASSERT_FALSE(decoded) << to_hex(pdu);
    EXPECT_EQ(decoded.error().exception, refusal) << to_hex(pdu) << ": " << decoded.error().field;
}

TEST(RequestTemplates, SamplesAreTheSpecsLayouts) {
    ASSERT_EQ(std::size(kSamples), request_templates().size());
    for (const Sample& expected : kSamples) {
        SCOPED_TRACE(expected.sample);
        const RequestTemplate* row = find_template(expected.code);
        ASSERT_NE(row, nullptr);
        const auto sample = sample_request(expected.code);
        if (*expected.sample == '\0') {
            EXPECT_FALSE(sample);
            continue;
        }
        ASSERT_TRUE(sample);
        EXPECT_EQ(to_hex(*sample), expected.sample);
        expect_accepted(*sample);
        const char* harmless = *expected.harmless == '\0' ? expected.sample : expected.harmless;
        EXPECT_EQ(to_hex(*harmless_request(expected.code)), harmless);
    }
}

TEST(RequestTemplates, HarmlessWritesAreRefusedWith03) {
    for (const RequestTemplate& row : request_templates()) {
        const auto code = static_cast<std::uint8_t>(row.code);
        if (!writes(code)) {
            EXPECT_TRUE(row.harmless.empty()) << row.sample;
        } else if (!row.harmless.empty()) {
            expect_refused(*harmless_request(code), k03);
        }
    }
}

TEST(RequestTemplates, BoundedFieldsAreTheSpecsLimits) {
    std::size_t bounded = 0;
    for (const RequestTemplate& row : request_templates()) {
        for (const RequestField& field : row.fields) {
            if (!is_bounded(field)) continue;
            ++bounded;
            const auto code = static_cast<std::uint8_t>(row.code);
            const auto* spec = std::find_if(
                std::begin(kSpecLimits), std::end(kSpecLimits),
                [&](const SpecLimit& s) { return s.code == code && field.name == s.field; });
            ASSERT_NE(spec, std::end(kSpecLimits)) << int{code} << " " << field.name;
            EXPECT_EQ(field.min, spec->min) << field.name;
            EXPECT_EQ(field.max, spec->max) << field.name;
            EXPECT_EQ(field.refusal, spec->refusal) << field.name;
        }
    }
    EXPECT_EQ(bounded, std::size(kSpecLimits));
}

TEST(RequestTemplates, TheParserAcceptsEachLimitAndRefusesOnePast) {
    for (const RequestTemplate& row : request_templates()) {
        for (const RequestField& field : row.fields) {
            if (!is_bounded(field)) continue;
            SCOPED_TRACE(std::string(function_name(static_cast<std::uint8_t>(row.code))) + ", " +
                         std::string(field.name));
            expect_accepted(with_value(row, field, field.min));
            expect_accepted(with_value(row, field, field.max));
            if (field.min > 0) expect_refused(with_value(row, field, field.min - 1), field.refusal);
            const unsigned widest = field.width == 1 ? 0xFF : 0xFFFF;
            if (field.max < widest)
                expect_refused(with_value(row, field, field.max + 1), field.refusal);
        }
    }
}

TEST(RequestTemplates, CoilValuesAreOnOrOff) {
    const RequestTemplate& row = *find_template(0x05);
    const RequestField& value = row.fields.items[1];
    ASSERT_EQ(value.rule, FieldRule::CoilValue);
    expect_accepted(with_value(row, value, 0xFF00));
    expect_accepted(with_value(row, value, 0x0000));
    expect_refused(with_value(row, value, 0xFF01), k03);
    expect_refused(with_value(row, value, 0x00FF), k03);
}

TEST(RequestTemplates, ByteCountsFollowTheirQuantity) {
    for (const RequestTemplate& row : request_templates()) {
        for (std::size_t i = 1; i < row.fields.size; ++i) {
            const RequestField& count = row.fields.items[i];
            if (count.rule != FieldRule::BitBytes && count.rule != FieldRule::RegisterBytes)
                continue;
            SCOPED_TRACE(row.sample);
            // Nine bits take two bytes, nine registers eighteen; one byte less is refused.
            auto pdu = with_value(row, row.fields.items[i - 1], 9);
            EXPECT_EQ(pdu[count.offset], count.rule == FieldRule::BitBytes ? 2 : 18);
            expect_accepted(pdu);
            pdu[count.offset] = static_cast<std::uint8_t>(pdu[count.offset] - 1);
            pdu.pop_back();
            expect_refused(pdu, k03);
        }
    }
}

TEST(RequestTemplates, RangeFieldsAreWhereTheParserReadsThem) {
    // FC 17 writes the range its Address and Quantity name; FC 03 reads it.
    const auto pdu = hex("17 00 01 00 02 00 03 00 04 08 00 00 00 00 00 00 00 00");
    const RequestTemplate& rw = *find_template(0x17);
    EXPECT_EQ(read_field(pdu, *field_with(rw, FieldRole::ReadAddress)), 1);
    EXPECT_EQ(read_field(pdu, *field_with(rw, FieldRole::ReadQuantity)), 2);
    EXPECT_EQ(read_field(pdu, *field_with(rw, FieldRole::Address)), 3);
    EXPECT_EQ(read_field(pdu, *field_with(rw, FieldRole::Quantity)), 4);
    EXPECT_FALSE(
        read_field(hex("03 00 01 00"), *field_with(*find_template(0x03), FieldRole::Quantity)));
    EXPECT_EQ(find_template(0x2A), nullptr);
}

TEST(RequestTemplates, TablesAndWritesAgreeWithTheFunctionTable) {
    EXPECT_EQ(find_template(0x01)->table, DataTable::Coils);
    EXPECT_EQ(find_template(0x02)->table, DataTable::DiscreteInputs);
    EXPECT_EQ(find_template(0x04)->table, DataTable::InputRegisters);
    EXPECT_EQ(find_template(0x17)->table, DataTable::HoldingRegisters);
    EXPECT_EQ(find_template(0x15)->table, DataTable::FileRecords);
    for (const FunctionRow& row : kFunctionTable) {
        const auto code = static_cast<std::uint8_t>(row.code);
        EXPECT_EQ(writes(code), row.writes == Writes::Yes) << int{code};
        // What a write writes back is in a table FC 01 or FC 03 reads.
        const RequestTemplate& request = *find_template(code);
        if (request.value_form != ValueForm::None) {
            EXPECT_TRUE(writes(code));
            EXPECT_TRUE(request.table == DataTable::Coils ||
                        request.table == DataTable::HoldingRegisters);
        }
    }
}

}  // namespace
}  // namespace mblab::protocol
