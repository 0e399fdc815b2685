#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

// Beside each row of kFunctionTable, the request's layout as [APP] section 6 draws it: its fields
// with their limits, the data table it touches, a plain sample request, a harmless one, and the
// names of its answer's fields. The tester, the load generator and the fuzzer build and judge
// requests from these rows instead of keeping their own copies; the codec's checks use the same
// limits (limits.hpp), and tests/unit/protocol/test_request_templates.cpp holds both to [APP].
namespace mblab::protocol {

// The data a request reads or writes ([APP] 4.3).
enum class DataTable : std::uint8_t {
    None,
    Coils,
    DiscreteInputs,
    HoldingRegisters,  // also FC 18's FIFO pointer, a holding register address
    InputRegisters,
    FileRecords,
};

// What a field means to callers that look for it by meaning rather than by position.
enum class FieldRole : std::uint8_t {
    Other,
    Address,      // the first address acted on; for FC 17, the first one written
    Quantity,     // how many from Address; for FC 17, how many are written
    ReadAddress,  // FC 17's read range
    ReadQuantity,
    ByteCount,  // bytes that follow
};

enum class FieldRule : std::uint8_t {
    Any,            // every value is well-formed (checks that depend on the device aside)
    Range,          // min..max, else `refusal`
    CoilValue,      // 0x0000 or 0xFF00, else 03 ([APP] 6.5)
    BitBytes,       // the quantity before it in bytes of 8 bits, rounded up, else 03
    RegisterBytes,  // 2 x the quantity before it, else 03
    CountsRest,     // min..max and exactly the bytes after it, else 03
};

struct RequestField {
    std::string_view name;
    std::uint8_t offset = 0;  // in the PDU; the function code is byte 0
    std::uint8_t width = 2;   // bytes, big-endian
    FieldRole role = FieldRole::Other;
    FieldRule rule = FieldRule::Any;
    std::uint16_t min = 0;
    std::uint16_t max = 0xFFFF;
    ExceptionCode refusal = ExceptionCode::IllegalDataValue;
};

// A field of the answer, by name only: reports say which byte of an answer differs.
struct AnswerField {
    std::string_view name;
    std::uint8_t offset = 0;  // in the PDU
    std::uint8_t width = 1;
};

// How the sample request carries the value it writes, so that a write of what is there already
// can be made from it (conformance/plain_requests.cpp).
enum class ValueForm : std::uint8_t {
    None,        // writes nothing read back by FC 01 / 03, or its sample keeps the value
    CoilWord,    // FC 05: 0xFF00 on, 0x0000 off
    PackedBits,  // FC 0F: bit 0 of a byte
    Word,        // a register's two bytes
};

// A short list kept inside a constexpr row.
template <class T, std::size_t N>
struct FixedList {
    std::array<T, N> items{};
    std::size_t size = 0;

    constexpr FixedList() = default;
    constexpr FixedList(std::initializer_list<T> list) {
        for (const T& item : list)
            items[size++] = item;
    }
    constexpr const T* begin() const { return items.data(); }
    constexpr const T* end() const { return items.data() + size; }
};

struct RequestTemplate {
    FunctionCode code{};
    DataTable table = DataTable::None;
    FixedList<RequestField, 5> fields{};
    // Hex of a well-formed request at address 0 with the smallest quantity, which a device serving
    // the function answers with data or with an exception other than 01; empty when no request is
    // plain to every device.
    std::string_view sample{};
    // For a writing function, a request the device must refuse with 03 before changing anything;
    // empty: the sample itself changes nothing.
    std::string_view harmless{};
    ValueForm value_form = ValueForm::None;
    std::uint8_t value_at = 0;  // PDU offset of the written value in the sample
    FixedList<AnswerField, 6> answer{};
    std::string_view answer_rest = "data";  // what the answer's bytes past its fields hold
};

// One per row of kFunctionTable, in its order (static_asserts in request_template.cpp).
std::span<const RequestTemplate> request_templates();

// The template of `code`, or nullptr for a code without a row.
const RequestTemplate* find_template(std::uint8_t code);

// The first field of `request` with `role`, or nullptr.
const RequestField* field_with(const RequestTemplate& request, FieldRole role);

// The field's value in `pdu`, or nullopt when the PDU is cut before its end.
std::optional<std::uint16_t> read_field(std::span<const std::uint8_t> pdu,
                                        const RequestField& field);
// Writes `value` into the field; `pdu` must hold it.
void write_field(std::span<std::uint8_t> pdu, const RequestField& field, std::uint16_t value);

// The sample request of `code` as bytes; nullopt without a template or a sample.
std::optional<std::vector<std::uint8_t>> sample_request(std::uint8_t code);
// The harmless request of `code`: the sample where that changes nothing.
std::optional<std::vector<std::uint8_t>> harmless_request(std::uint8_t code);

// Whether `code` changes what it names (the Writes column of kFunctionTable).
bool writes(std::uint8_t code);

}  // namespace mblab::protocol
