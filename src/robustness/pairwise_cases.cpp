#include "robustness/pairwise_cases.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <initializer_list>
#include <span>
#include <string_view>

#include "protocol/request_template.hpp"
#include "robustness/in_turn.hpp"
#include "robustness/pairwise.hpp"
#include "robustness/request_bytes.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

// How a field goes on the wire, which bounds its values: a relative value that falls outside
// wraps as the wire would (a byte count of right - 1 for 0 is 0xFF); a count is never below 0.
enum class Width : std::uint8_t { Word, Byte, Count };

// A number, or an offset from the right value, which the fields before it decide (a byte count
// from the quantity, the MBAP length from the PDU).
struct Value {
    std::int64_t number = 0;
    bool relative = false;
};

constexpr Value right(std::int64_t offset = 0) {
    return {offset, true};
}

struct Field {
    std::string_view name;
    Width width = Width::Word;
    bool hex = false;
    std::vector<Value>
        values;  // the nominal one first: the covering array fills spare slots with it
    // The transaction and protocol ids are named only when they are not the usual ones.
    bool named_when_nominal = true;
};

// The values, repeats left out (the check address may be 0 or 1).
std::vector<Value> exact(const std::vector<std::int64_t>& numbers) {
    std::vector<Value> out;
    for (auto number : numbers) {
        if (std::none_of(out.begin(), out.end(),
                         [&](const Value& v) { return !v.relative && v.number == number; }))
            out.push_back({number, false});
    }
    return out;
}

enum class Layout : std::uint8_t {
    Words,          // FC 01 to 06, 16: 16-bit fields only
    MultipleWrite,  // FC 0F, 10: address, quantity, byte count, data bytes
    ReadWrite,      // FC 17: read and write ranges, byte count (as much data as it says)
    Diagnostics,    // FC 08: sub-function, data word, data bytes
    DeviceId,       // FC 2B: MEI type, read code, object id
};

struct Request {
    std::uint8_t function;
    Layout layout;
    std::vector<Field> fields;
};

// One row's values, resolved field by field, each adding its words to the case's name.
class Pick {
  public:
    Pick(std::span<const Field> fields, std::span<const std::size_t> row)
        : fields_(fields), row_(row), said_(fields.size()) {}

    std::uint16_t operator()(std::size_t i, std::int64_t right_value = 0) {
        const Field& field = fields_[i];
        const Value& value = field.values[row_[i]];
        std::int64_t number = value.relative ? right_value + value.number : value.number;
        switch (field.width) {
            case Width::Word:
                number &= 0xFFFF;
                break;
            case Width::Byte:
                number &= 0xFF;
                break;
            case Width::Count:
                number = std::max<std::int64_t>(number, 0);
                break;
        }
        if (row_[i] != 0 || field.named_when_nominal) {
            if (value.relative && value.number == 0)
                said_[i] = fmt::format(" {} right", field.name);
            else if (value.relative)
                said_[i] = fmt::format(" {} right{:+} ({})", field.name, value.number, number);
            else if (field.hex)
                said_[i] = fmt::format(" {} 0x{:0{}X}", field.name, number,
                                       field.width == Width::Byte ? 2 : 4);
            else
                said_[i] = fmt::format(" {} {}", field.name, number);
        }
        return static_cast<std::uint16_t>(number);
    }

    bool nominal(std::size_t i) const { return row_[i] == 0; }
    const std::string& said(std::size_t i) const { return said_[i]; }

  private:
    std::span<const Field> fields_;
    std::span<const std::size_t> row_;
    std::vector<std::string> said_;
};

Bytes build(const Request& request, Pick& pick) {
    const std::uint8_t function = request.function;
    switch (request.layout) {
        case Layout::MultipleWrite: {
            const auto address = pick(0);
            const auto quantity = pick(1);
            const auto count =
                static_cast<std::uint8_t>(pick(2, byte_count_for(function, quantity)));
            return multiple_write(function, address, quantity, count, pick(3, count));
        }
        case Layout::ReadWrite: {
            const auto read_address = pick(0);
            const auto read_quantity = pick(1);
            const auto write_address = pick(2);
            const auto write_quantity = pick(3);
            const auto count =
                static_cast<std::uint8_t>(pick(4, byte_count_for(0x17, write_quantity)));
            return read_write(read_address, read_quantity, write_address, write_quantity, count,
                              count);
        }
        case Layout::Diagnostics: {
            Bytes pdu = words(function, {pick(0), pick(1)});
            // Cut into the data word, or more bytes after it (0xA5, as the echo class has them).
            pdu.resize(3 + pick(2, 2), 0xA5);
            return pdu;
        }
        case Layout::DeviceId:
            return {function, static_cast<std::uint8_t>(pick(0)),
                    static_cast<std::uint8_t>(pick(1)), static_cast<std::uint8_t>(pick(2))};
        case Layout::Words:
            break;
    }
    Bytes pdu{function};
    for (std::size_t i = 0; i < request.fields.size(); ++i)
        put16(pdu, pick(i));
    return pdu;
}

std::vector<Request> requests(const Recon& recon, const std::optional<WritableRange>& writable) {
    const std::int64_t check = recon.check_address;
    const Field register_address{"address", Width::Word, true,
                                 exact({check, 0, 1, 0x7FFF, 0xFFFE, 0xFFFF})};
    const Field bit_address{"address", Width::Word, true,
                            exact({0, 1, check, 0x7FFF, 0xFFFE, 0xFFFF})};
    // The writable range's first and last address and the one past it; 1 is left out for writes,
    // which already have many rows, and 0x7FFF kept: signed address arithmetic turns there.
    std::vector<Value> writes = exact({0, 0x7FFF, 0xFFFE, 0xFFFF});
    if (writable && writable->count > 0) {
        const std::int64_t start = writable->start;
        writes = exact({start, start + writable->count - 1, (start + writable->count) & 0xFFFF, 0,
                        0x7FFF, 0xFFFE, 0xFFFF});
    }
    const Field write_address{"address", Width::Word, true, writes};
    // 1, 0, `before`, the request template's limit and one past it ([APP] 6), then `after`.
    auto quantity = [](std::string_view name, std::uint8_t function,
                       std::initializer_list<std::int64_t> before = {},
                       std::initializer_list<std::int64_t> after = {0x7FFF, 0xFFFE, 0xFFFF},
                       protocol::FieldRole role = protocol::FieldRole::Quantity) {
        const std::int64_t limit =
            protocol::field_with(*protocol::find_template(function), role)->max;
        std::vector<std::int64_t> numbers = {1, 0};
        numbers.insert(numbers.end(), before);
        numbers.insert(numbers.end(), {limit, limit + 1});
        numbers.insert(numbers.end(), after);
        return Field{name, Width::Word, false, exact(numbers)};
    };
    const Field byte_count{"byte count",
                           Width::Byte,
                           false,
                           {right(), right(-1), right(1), {0, false}, {0xFF, false}}};
    const Field data{"data bytes", Width::Count, false, {right(), right(-1), right(1), {0, false}}};
    const std::int64_t max_read = recon.max_read;

    std::vector<Request> all = {
        {0x01, Layout::Words, {bit_address, quantity("quantity", 0x01)}},
        {0x02, Layout::Words, {bit_address, quantity("quantity", 0x02)}},
        {0x03, Layout::Words, {register_address, quantity("quantity", 0x03, {max_read})}},
        {0x04, Layout::Words, {register_address, quantity("quantity", 0x04)}},
        {0x05,
         Layout::Words,
         {write_address,
          {"value", Width::Word, true,
           exact({0xFF00, 0x0000, 0x0001, 0x00FF, 0xFF01, 0x7FFF, 0xFFFF})}}},
        {0x06,
         Layout::Words,
         {write_address,
          {"value", Width::Word, true, exact({0x0000, 0x0001, 0x7FFF, 0x8000, 0xFFFF})}}},
        // Sub-functions 03 (change the ASCII delimiter) and 04 (listen only) are left to the
        // sub-function class: a device that obeys them stops answering, rightly, for the rest of
        // the run. 01 (restart) is withheld unless writes are allowed.
        {0x08,
         Layout::Diagnostics,
         {{"sub-function", Width::Word, true,
           exact({0x0000, 0x0001, 0x000A, 0x000B, 0x0012, 0x0015, 0x00FF, 0xFFFF})},
          {"data", Width::Word, true, exact({0x0000, 0xFF00, 0xFFFF})},
          {"data bytes",
           Width::Count,
           false,
           {right(), {0, false}, {1, false}, {4, false}, {250, false}}}}},
        {0x0F,
         Layout::MultipleWrite,
         {write_address, quantity("quantity", 0x0F), byte_count, data}},
        {0x10,
         Layout::MultipleWrite,
         {write_address, quantity("quantity", 0x10), byte_count, data}},
        {0x16,
         Layout::Words,
         {write_address,
          {"and mask", Width::Word, true, exact({0xFFFF, 0x0000, 0xFF00})},
          {"or mask", Width::Word, true, exact({0x0000, 0xFFFF, 0x00FF})}}},
        {0x17,
         Layout::ReadWrite,
         {{"read address", Width::Word, true, exact({check, 0, 0x7FFF, 0xFFFF})},
          quantity("read quantity", 0x17, {}, {0xFFFF}, protocol::FieldRole::ReadQuantity),
          {"write address", Width::Word, true, writes},
          quantity("write quantity", 0x17, {}, {0xFFFF}),
          byte_count}},
        {0x2B,
         Layout::DeviceId,
         {{"MEI type", Width::Byte, true, exact({0x0E, 0x0D, 0x00, 0xFF})},
          {"read code", Width::Byte, true, exact({0x01, 0x02, 0x03, 0x04, 0x00, 0x05, 0xFF})},
          {"object id", Width::Byte, true, exact({0x00, 0x02, 0x03, 0x07, 0x80, 0xFF})}}},
    };
    return all;
}

// The header fields, after the request's: the unit id always, the MBAP ones over Modbus/TCP. On
// a line the unit id is the address: a device parses what is sent to it or broadcast (address 0,
// executed and never answered), and drops the rest unread, so other addresses try nothing there.
std::vector<Field> header_fields(std::uint8_t unit, bool mbap) {
    const std::int64_t other = unit == 1 ? 2 : 1;
    std::vector<Field> out = {
        {"unit", Width::Byte, false, mbap ? exact({unit, 0, 255, 247, other}) : exact({unit, 0})}};
    if (mbap) {
        out.push_back({"length",
                       Width::Word,
                       false,
                       {right(), {0, false}, {1, false}, right(-1), right(1), {255, false}}});
        out.push_back({"protocol", Width::Word, true, exact({0, 1}), false});
        // The first is the generator's own count, which the request does not decide.
        out.push_back(
            {"transaction", Width::Word, true, {right(), {0, false}, {0xFFFF, false}}, false});
    }
    return out;
}

PairwiseFrame frame_of(const Request& request, std::span<const Field> fields,
                       std::span<const std::size_t> row, bool mbap) {
    const std::size_t at = request.fields.size();  // the header fields follow the request's
    Pick pick(fields, row);
    PairwiseFrame frame;
    frame.pdu = build(request, pick);
    frame.unit = static_cast<std::uint8_t>(pick(at));
    if (mbap) {
        const auto length = pick(at + 1, static_cast<std::int64_t>(frame.pdu.size()) + 1);
        if (!pick.nominal(at + 1)) frame.length = length;
        frame.protocol = pick(at + 2);
        const auto transaction = pick(at + 3);
        if (!pick.nominal(at + 3)) frame.transaction = transaction;
    }
    frame.name = fmt::format("FC 0x{:02X}{}", request.function, pick.said(at));
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i != at) frame.name += pick.said(i);
    }
    return frame;
}

}  // namespace

std::vector<PairwiseFrame> pairwise_frames(const Recon& recon,
                                           const std::optional<WritableRange>& writable,
                                           bool mbap) {
    std::vector<std::vector<PairwiseFrame>> by_function;
    for (const auto& request : requests(recon, writable)) {
        std::vector<Field> fields = request.fields;
        for (auto& field : header_fields(recon.unit, mbap))
            fields.push_back(std::move(field));
        std::vector<std::size_t> counts;
        for (const auto& field : fields)
            counts.push_back(field.values.size());
        auto& frames = by_function.emplace_back();
        for (const auto& row : pairwise_rows(counts))
            frames.push_back(frame_of(request, fields, row, mbap));
    }
    return in_turn(std::move(by_function));
}

}  // namespace mblab::robustness
