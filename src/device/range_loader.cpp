#include <bit>
#include <cmath>
#include <limits>

#include "device/profile_loader.hpp"
#include "device/profile_sections.hpp"

namespace mblab::device {

namespace {

constexpr std::uint32_t kAddressSpace = 65536;

std::uint32_t type_width(ValueType type) {
    return type == ValueType::U32 || type == ValueType::F32 ? 2 : 1;
}

// Appends the registers (or bit) one TOML value stands for; reports a wrong type or range.
bool encode_value(const toml::node& node, const std::string& path, ValueType type,
                  ProfileErrors& errors, std::vector<std::uint16_t>& out) {
    std::int64_t integer = 0;
    switch (type) {
        case ValueType::Bit:
            if (auto b = node.as_boolean()) {
                out.push_back(**b ? 1 : 0);
                return true;
            }
            if (!array_integer(node, path, 0, 1, errors, integer)) return false;
            out.push_back(static_cast<std::uint16_t>(integer));
            return true;
        case ValueType::U16:
            if (!array_integer(node, path, 0, 0xFFFF, errors, integer)) return false;
            out.push_back(static_cast<std::uint16_t>(integer));
            return true;
        case ValueType::I16:
            if (!array_integer(node, path, -32768, 32767, errors, integer)) return false;
            out.push_back(static_cast<std::uint16_t>(integer));
            return true;
        case ValueType::U32:
            if (!array_integer(node, path, 0, 0xFFFFFFFF, errors, integer)) return false;
            out.push_back(static_cast<std::uint16_t>(integer >> 16));
            out.push_back(static_cast<std::uint16_t>(integer & 0xFFFF));
            return true;
        case ValueType::F32: {
            double number = 0;
            if (auto i = node.as_integer()) {
                number = static_cast<double>(**i);
            } else if (auto f = node.as_floating_point()) {
                number = **f;
            } else {
                errors.fail(node.source(), path, "expected a number, got " + describe_node(node));
                return false;
            }
            if (std::isfinite(number) &&
                std::fabs(number) > static_cast<double>(std::numeric_limits<float>::max())) {
                errors.fail(node.source(), path, "the number does not fit a 32-bit float");
                return false;
            }
            const auto bits = std::bit_cast<std::uint32_t>(static_cast<float>(number));
            out.push_back(static_cast<std::uint16_t>(bits >> 16));
            out.push_back(static_cast<std::uint16_t>(bits & 0xFFFF));
            return true;
        }
        case ValueType::String: {
            auto s = node.as_string();
            if (!s) {
                errors.fail(node.source(), path, "expected a string, got " + describe_node(node));
                return false;
            }
            const std::string& text = **s;
            for (std::size_t i = 0; i < text.size(); i += 2) {
                const auto high = static_cast<std::uint8_t>(text[i]);
                const auto low = i + 1 < text.size() ? static_cast<std::uint8_t>(text[i + 1]) : 0;
                out.push_back(static_cast<std::uint16_t>(high << 8 | low));
            }
            return true;
        }
    }
    return false;
}

}  // namespace

bool load_range(const toml::table& table, const std::string& path, BankKind kind,
                ProfileErrors& errors, RangeSpec& out) {
    Fields fields(table, path, errors);
    const bool bits = is_bit_bank(kind);
    const bool writable = kind == BankKind::Coils || kind == BankKind::HoldingRegisters;
    out.access = writable ? Access::ReadWrite : Access::ReadOnly;
    out.type = bits ? ValueType::Bit : ValueType::U16;

    if (!fields.require("start", "give the first address, e.g. start = 0")) return false;
    fields.integer_as("start", out.start, 0, kAddressSpace - 1);
    fields.choice<Access>(
        "access", out.access,
        {{"ro", Access::ReadOnly}, {"rw", Access::ReadWrite}, {"wo", Access::WriteOnly}});
    if (bits) {
        fields.choice<ValueType>("type", out.type, {{"bit", ValueType::Bit}});
    } else {
        fields.choice<ValueType>("type", out.type,
                                 {{"u16", ValueType::U16},
                                  {"i16", ValueType::I16},
                                  {"u32", ValueType::U32},
                                  {"f32", ValueType::F32},
                                  {"string", ValueType::String}});
    }
    fields.string("name", out.name);
    fields.string("description", out.description);
    if (fields.failed()) return false;

    const std::uint32_t room = kAddressSpace - out.start;
    std::uint32_t count = 0;
    const bool has_count = fields.integer_as("count", count, 1, room);
    if (fields.failed()) return false;

    const toml::node* value = fields.get("value");
    const toml::node* values = fields.get("values");
    if (value && values) {
        fields.fail("values", "give either value (one value for every address) or values (a list)");
        return false;
    }
    const std::uint32_t width = type_width(out.type);
    std::vector<std::uint16_t> encoded;
    if (values) {
        const toml::array* list = values->as_array();
        if (!list) {
            fields.fail("values", "expected an array, got " + describe_node(*values));
            return false;
        }
        if (out.type == ValueType::String) {
            fields.fail("values", "a string range takes one value, e.g. value = \"text\"");
            return false;
        }
        for (std::size_t i = 0; i < list->size(); ++i) {
            const std::string element = fields.path("values") + "[" + std::to_string(i) + "]";
            if (!encode_value(*list->get(i), element, out.type, errors, encoded)) return false;
        }
    } else if (value) {
        if (!encode_value(*value, fields.path("value"), out.type, errors, encoded)) return false;
    }

    if (!has_count) {
        count = values || out.type == ValueType::String ? static_cast<std::uint32_t>(encoded.size())
                                                        : width;
        if (count == 0) count = 1;
    }
    if (count > room) {
        fields.fail(value ? "value" : "values",
                    "the range would end past address 65535; it needs " + std::to_string(count) +
                        " addresses from " + std::to_string(out.start));
        return false;
    }
    if (count % width != 0) {
        fields.fail("count", "a u32 or f32 range takes an even number of registers, got " +
                                 std::to_string(count));
        return false;
    }
    if (encoded.size() > count) {
        fields.fail(value ? "value" : "values",
                    "the value needs " + std::to_string(encoded.size()) +
                        " addresses but count is " + std::to_string(count));
        return false;
    }
    out.count = count;
    out.values.assign(count, 0);
    if (value && out.type != ValueType::String && !encoded.empty()) {
        for (std::uint32_t i = 0; i < count; ++i)
            out.values[i] = encoded[i % encoded.size()];
    } else {
        std::copy(encoded.begin(), encoded.end(), out.values.begin());
    }
    fields.finish();
    return !fields.failed();
}

}  // namespace mblab::device
