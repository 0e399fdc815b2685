#include "load/mix.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <iterator>
#include <optional>

#include "protocol/function_code.hpp"
#include "protocol/request_template.hpp"

namespace mblab::load {

namespace {

using protocol::FunctionCode;

// Write data the generator sends: fixed, so a request is built once and only its transaction
// id changes on the wire.
constexpr std::uint16_t kRegisterValue = 0x1234;
constexpr std::uint8_t kCoilBits = 0x55;
constexpr std::uint16_t kCoilOn = 0xFF00;
constexpr std::uint16_t kDefaultWriteAddress = 0x0010;

// The codes mix_exchange builds (kMixFunctions); their limits and whether they write are the
// request templates'.
constexpr std::uint8_t kMixCodes[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10};

struct FunctionRule {
    std::uint8_t code;
    std::uint16_t max_quantity;  // 1 for the single writes
    bool writes;
};

std::optional<FunctionRule> find_rule(std::uint8_t code) {
    if (std::find(std::begin(kMixCodes), std::end(kMixCodes), code) == std::end(kMixCodes))
        return std::nullopt;
    const auto* quantity =
        protocol::field_with(*protocol::find_template(code), protocol::FieldRole::Quantity);
    return FunctionRule{code, quantity != nullptr ? quantity->max : std::uint16_t{1},
                        protocol::writes(code)};
}

// Decimal, or hex after 0x; the whole text must be the number.
bool parse_number(std::string_view text, std::uint64_t max, std::uint64_t& out) {
    int base = 10;
    if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        text.remove_prefix(2);
        base = 16;
    }
    if (text.empty()) return false;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, base);
    return ec == std::errc() && end == text.data() + text.size() && out <= max;
}

// Splits `text` at the first `mark`: what comes before stays in `text`, the rest is returned.
std::string_view cut(std::string_view& text, char mark) {
    auto at = text.find(mark);
    if (at == std::string_view::npos) return {};
    std::string_view after = text.substr(at + 1);
    text = text.substr(0, at);
    return after;
}

protocol::Result<MixEntry, std::string> parse_entry(std::string_view text) {
    auto bad = [&](const std::string& why) {
        return fmt::format(
            "--mix entry '{}': {} (expected fcCODE[:QUANTITY][@ADDRESS][=WEIGHT], "
            "e.g. fc3:125=70)",
            text, why);
    };
    MixEntry entry;
    std::string_view rest = text;
    const bool has_weight = rest.find('=') != std::string_view::npos;
    const std::string_view weight = cut(rest, '=');
    entry.text = std::string(rest);
    const bool has_address = rest.find('@') != std::string_view::npos;
    const std::string_view address = cut(rest, '@');
    const bool has_quantity = rest.find(':') != std::string_view::npos;
    const std::string_view quantity = cut(rest, ':');
    if (!rest.starts_with("fc")) return bad("it must start with fc");
    std::uint64_t value = 0;
    if (!parse_number(rest.substr(2), 0xFF, value)) return bad("the function code is not a number");
    const auto rule = find_rule(static_cast<std::uint8_t>(value));
    if (!rule) {
        return bad(fmt::format("function {} is not one the generator sends ({})", rest.substr(2),
                               kMixFunctions));
    }
    entry.function = rule->code;
    if (has_quantity) {
        if (!parse_number(quantity, rule->max_quantity, value) || value == 0) {
            return bad(fmt::format("the quantity must be 1..{} for {}", rule->max_quantity,
                                   protocol::function_name(rule->code)));
        }
        entry.quantity = static_cast<std::uint16_t>(value);
    }
    entry.address = rule->writes ? kDefaultWriteAddress : 0;
    if (has_address) {
        if (!parse_number(address, 0xFFFF, value)) return bad("the address must be 0..65535");
        entry.address = static_cast<std::uint16_t>(value);
    }
    if (std::uint32_t{entry.address} + entry.quantity > 0x10000) {
        return bad("the range runs past address 65535");
    }
    if (has_weight) {
        if (!parse_number(weight, 1'000'000, value) || value == 0) {
            return bad("the weight must be 1..1000000");
        }
        entry.weight = static_cast<std::uint32_t>(value);
    }
    return entry;
}

// The MBAP header up to and including the unit id; transaction id 0, {len} computed.
conformance::Pattern header() {
    conformance::Pattern p;
    p.u16(0).u16(0).length().fact("unit");
    return p;
}

}  // namespace

protocol::Result<std::vector<MixEntry>, std::string> parse_mix(std::string_view text) {
    std::vector<MixEntry> entries;
    while (!text.empty()) {
        auto comma = text.find(',');
        std::string_view item = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
        if (item.empty()) continue;
        auto entry = parse_entry(item);
        if (!entry) return entry.error();
        entries.push_back(std::move(entry.value()));
    }
    if (entries.empty()) return std::string("--mix names no requests");
    return entries;
}

MixExchange mix_exchange(const MixEntry& entry) {
    MixExchange out{header(), header()};
    const std::uint8_t fc = entry.function;
    conformance::Pattern& request = out.request.byte(fc).u16(entry.address);
    conformance::Pattern& expect = out.expect.byte(fc);
    const std::size_t bit_bytes = (std::size_t{entry.quantity} + 7) / 8;
    switch (static_cast<FunctionCode>(fc)) {
        case FunctionCode::ReadCoils:
        case FunctionCode::ReadDiscreteInputs:
            request.u16(entry.quantity);
            expect.byte(static_cast<std::uint8_t>(bit_bytes)).any(bit_bytes);
            break;
        case FunctionCode::WriteSingleCoil:
            request.u16(kCoilOn);
            expect.u16(entry.address).u16(kCoilOn);
            break;
        case FunctionCode::WriteSingleRegister:
            request.u16(kRegisterValue);
            expect.u16(entry.address).u16(kRegisterValue);
            break;
        case FunctionCode::WriteMultipleCoils: {
            request.u16(entry.quantity).byte(static_cast<std::uint8_t>(bit_bytes));
            for (std::size_t i = 0; i < bit_bytes; ++i) {
                // Bits past the quantity are sent as 0.
                const std::size_t bits = std::min<std::size_t>(8, entry.quantity - i * 8);
                request.byte(static_cast<std::uint8_t>(kCoilBits & ((1U << bits) - 1)));
            }
            expect.u16(entry.address).u16(entry.quantity);
            break;
        }
        case FunctionCode::WriteMultipleRegisters:
            request.u16(entry.quantity).byte(static_cast<std::uint8_t>(entry.quantity * 2));
            for (std::size_t i = 0; i < entry.quantity; ++i)
                request.u16(kRegisterValue);
            expect.u16(entry.address).u16(entry.quantity);
            break;
        default:  // 03, 04
            request.u16(entry.quantity);
            expect.byte(static_cast<std::uint8_t>(entry.quantity * 2)).any(entry.quantity * 2U);
            break;
    }
    return out;
}

}  // namespace mblab::load
