#include "server/journaled_device.hpp"

#include <optional>
#include <vector>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "support/hex_digits.hpp"

namespace mblab::server {

namespace {

// The answer for a write that could not be made durable.
void device_failure(std::uint8_t function, device::Reply& reply, std::span<std::uint8_t> response) {
    response[0] = static_cast<std::uint8_t>(function | protocol::kExceptionBit);
    response[1] = static_cast<std::uint8_t>(protocol::ExceptionCode::ServerDeviceFailure);
    reply.size = 2;
}

void add_word(std::string& line, std::uint32_t word) {
    for (int shift = 12; shift >= 0; shift -= 4)
        line += kHexDigits[(word >> shift) & 0xFU];
}

// Four hex digits at `at`, or -1.
long word_at(std::string_view text, std::size_t at) {
    if (at + 4 > text.size()) return -1;
    long word = 0;
    for (std::size_t i = at; i < at + 4; ++i) {
        const int digit = upper_hex_value(text[i]);
        if (digit < 0) return -1;
        word = word * 16 + digit;
    }
    return word;
}

// The unit number every record starts with, 0..255, and where the space after it stands.
struct LeadingUnit {
    std::uint8_t unit;
    std::size_t space;
};

std::optional<LeadingUnit> leading_unit(std::string_view line) {
    const auto space = line.find(' ');
    if (space == std::string_view::npos || space == 0 || space > 3) return std::nullopt;
    unsigned unit = 0;
    for (std::size_t i = 0; i < space; ++i) {
        if (line[i] < '0' || line[i] > '9') return std::nullopt;
        unit = unit * 10 + static_cast<unsigned>(line[i] - '0');
    }
    if (unit > 255) return std::nullopt;
    return LeadingUnit{static_cast<std::uint8_t>(unit), space};
}

// "UNIT V C|H START HEX" back into set_values; false when the line is not one.
bool replay_values(device::ReferenceDevice& device, std::string_view line) {
    const auto lead = leading_unit(line);
    if (!lead) return false;
    const auto first = lead->space;
    if (line.size() < first + 5 || line.substr(first, 3) != " V " || line[first + 4] != ' ')
        return false;
    const char bank = line[first + 3];
    const auto rest = line.substr(first + 5);
    const long start = word_at(rest, 0);
    if ((bank != 'C' && bank != 'H') || start < 0 || rest.size() < 9 || rest[4] != ' ' ||
        (rest.size() - 5) % 4 != 0) {
        return false;
    }
    std::vector<std::uint16_t> values;
    for (std::size_t at = 5; at < rest.size(); at += 4) {
        const long word = word_at(rest, at);
        if (word < 0) return false;
        values.push_back(static_cast<std::uint16_t>(word));
    }
    // A unit or an address the profile no longer maps was refused when written: nothing to do.
    (void)device.data().set_values(
        lead->unit, bank == 'C' ? device::BankKind::Coils : device::BankKind::HoldingRegisters,
        static_cast<std::uint32_t>(start), values);
    return true;
}

}  // namespace

std::string journal_record(const device::RequestContext& context,
                           std::span<const std::uint8_t> request) {
    std::string line = std::to_string(context.unit);
    line += context.link == device::Link::Serial ? " S " : " T ";
    for (auto byte : request) {
        line += kHexDigits[byte >> 4];
        line += kHexDigits[byte & 0x0F];
    }
    return line;
}

bool parse_journal_record(std::string_view line, device::RequestContext& context,
                          std::vector<std::uint8_t>& request) {
    const auto lead = leading_unit(line);
    if (!lead) return false;
    const auto first = lead->space;
    if (line.size() < first + 3 || line[first + 2] != ' ') return false;
    const char link = line[first + 1];
    if (link != 'T' && link != 'S') return false;
    const auto hex = line.substr(first + 3);
    if (hex.empty() || hex.size() % 2 != 0) return false;
    request.clear();
    for (std::size_t i = 0; i < hex.size(); i += 2) {
        const int high = upper_hex_value(hex[i]);
        const int low = upper_hex_value(hex[i + 1]);
        if (high < 0 || low < 0) return false;
        request.push_back(static_cast<std::uint8_t>(high * 16 + low));
    }
    context.unit = lead->unit;
    context.link = link == 'S' ? device::Link::Serial : device::Link::Tcp;
    return true;
}

std::string values_record(std::uint8_t unit, device::BankKind kind, std::uint32_t start,
                          std::span<const std::uint16_t> values) {
    std::string line = std::to_string(unit);
    line += kind == device::BankKind::Coils ? " V C " : " V H ";
    add_word(line, start);
    line += ' ';
    for (auto value : values)
        add_word(line, value);
    return line;
}

bool replay_record(device::ReferenceDevice& device, std::string_view line) {
    device::RequestContext context;
    std::vector<std::uint8_t> request;
    if (parse_journal_record(line, context, request)) {
        // One the device refuses now (another profile) changed nothing when it was made either.
        (void)device.state().replay_write(context, request);
        return true;
    }
    return replay_values(device, line);
}

std::optional<device::Reply> JournaledDevice::handle_or_defer(const device::RequestContext& context,
                                                              std::span<const std::uint8_t> request,
                                                              std::span<std::uint8_t> response,
                                                              device::Deferral& deferral) {
    auto order = keeper_.lock_order();
    const auto before = device_.state().writes();
    auto reply = device_.handle(context, request, response);
    if (device_.state().writes() == before) return reply;
    if (reply.action != device::ReplyAction::Answer) {
        // Nothing acknowledges this write (a broadcast, a fault): record it, hold nothing back.
        keeper_.append_locked(journal_record(context, request), {});
        return reply;
    }
    auto answer = std::vector<std::uint8_t>(response.begin(), response.begin() + reply.size);
    keeper_.append_locked(journal_record(context, request),
                          [done = deferral.take(), reply, answer = std::move(answer),
                           function = request[0]](bool written) mutable {
                              if (!written) {
                                  answer.resize(2);
                                  device_failure(function, reply, answer);
                              }
                              done(reply, answer);
                          });
    return std::nullopt;
}

}  // namespace mblab::server
