#include "conformance/line_evidence.hpp"

#include <fmt/core.h>

#include <optional>

#include "client/hex_text.hpp"
#include "protocol/crc16.hpp"
#include "protocol/lrc.hpp"
#include "support/hex_digits.hpp"

namespace mblab::conformance {

namespace {

constexpr std::size_t kMbapHeaderCells = 6;  // transaction id, protocol id, length
constexpr std::string_view kAnyCell = "XX";
constexpr std::string_view kRestCell = "...";

// A lower-case digit is a framing error [SER 2.5.2], but it still says which byte it is.
std::optional<std::uint8_t> hex_digit(std::uint8_t c) {
    const int value = hex_value(static_cast<char>(c));
    if (value < 0) return std::nullopt;
    return static_cast<std::uint8_t>(value);
}

// The bytes a frame holds: as they are, or on ASCII those its hex digits spell after the ':'.
std::vector<std::uint8_t> frame_bytes(client::Framing framing, std::span<const std::uint8_t> wire) {
    if (framing != client::Framing::Ascii) return {wire.begin(), wire.end()};
    std::vector<std::uint8_t> out;
    if (wire.empty() || wire[0] != ':') return out;
    for (std::size_t i = 1; i + 1 < wire.size(); i += 2) {
        const auto high = hex_digit(wire[i]);
        const auto low = hex_digit(wire[i + 1]);
        if (!high || !low) break;
        out.push_back(static_cast<std::uint8_t>(*high << 4 | *low));
    }
    return out;
}

std::optional<std::uint8_t> cell_value(const std::string& cell) {
    if (cell.size() != 2) return std::nullopt;
    const auto high = hex_digit(static_cast<std::uint8_t>(cell[0]));
    const auto low = hex_digit(static_cast<std::uint8_t>(cell[1]));
    if (!high || !low) return std::nullopt;
    return static_cast<std::uint8_t>(*high << 4 | *low);
}

std::string cell(std::uint8_t value) {
    return fmt::format("{:02X}", value);
}

// The expected frame's cells on the line: the MBAP header goes, the CRC or LRC comes.
std::vector<std::string> line_cells(const std::vector<std::string>& notation,
                                    client::Framing framing) {
    std::vector<std::string> cells;
    if (notation.size() > kMbapHeaderCells)
        cells.assign(notation.begin() + kMbapHeaderCells, notation.end());
    if (cells.empty() || cells.back() == kRestCell) return cells;
    std::vector<std::uint8_t> fixed;
    for (const auto& c : cells) {
        if (auto value = cell_value(c)) fixed.push_back(*value);
    }
    const bool concrete = fixed.size() == cells.size();
    if (framing == client::Framing::Ascii) {
        cells.push_back(concrete ? cell(protocol::lrc(fixed)) : std::string(kAnyCell));
    } else {
        const std::uint16_t crc = protocol::crc16(fixed);
        cells.push_back(concrete ? cell(crc & 0xFF) : std::string(kAnyCell));
        cells.push_back(concrete ? cell(crc >> 8) : std::string(kAnyCell));
    }
    return cells;
}

// The bytes of `got` that differ from `cells`, as match() numbers them: a position past the
// received bytes is a byte missing, past the cells one too many.
std::vector<std::size_t> differing(const std::vector<std::string>& cells,
                                   std::span<const std::uint8_t> got) {
    std::vector<std::size_t> out;
    std::size_t i = 0;
    for (; i < cells.size(); ++i) {
        if (cells[i] == kRestCell) return out;
        const auto value = cell_value(cells[i]);
        if (i >= got.size() || (value && got[i] != *value)) out.push_back(i);
    }
    for (; i < got.size(); ++i)
        out.push_back(i);
    return out;
}

}  // namespace

void LineFrames::note(std::span<const std::uint8_t> notation, std::span<const std::uint8_t> wire) {
    auto [at, added] = frames_.insert_or_assign(
        {notation.begin(), notation.end()}, std::vector<std::uint8_t>(wire.begin(), wire.end()));
    if (!added) return;
    order_.push_back(at);
    if (order_.size() <= kKept) return;
    frames_.erase(order_.front());
    order_.pop_front();
}

void LineFrames::clear() {
    frames_.clear();
    order_.clear();
}

const std::vector<std::uint8_t>* LineFrames::wire_of(std::span<const std::uint8_t> notation) const {
    const auto found = frames_.find({notation.begin(), notation.end()});
    return found == frames_.end() ? nullptr : &found->second;
}

void show_as_on_line(Exchange& exchange, client::Framing framing, const LineFrames& frames) {
    if (framing == client::Framing::Mbap || exchange.framing != client::Framing::Mbap) return;
    exchange.framing = framing;
    if (const auto* wire = frames.wire_of(exchange.sent)) exchange.sent = *wire;
    // Only a whole frame was put in the notation; anything else came as it is.
    if (exchange.status == client::ReceiveStatus::Frame) {
        if (const auto* wire = frames.wire_of(exchange.received)) exchange.received = *wire;
    }
    if (exchange.silence_expected || exchange.match.expected_cells.empty()) return;
    exchange.match.expected_cells = line_cells(exchange.match.expected_cells, framing);
    exchange.match.differs =
        differing(exchange.match.expected_cells, frame_bytes(framing, exchange.received));
    exchange.expected = expected_text(exchange);
}

std::string frame_text(client::Framing framing, std::span<const std::uint8_t> bytes) {
    if (framing != client::Framing::Ascii) return client::hex_bytes(bytes);
    std::string out;
    for (const std::uint8_t c : bytes) {
        if (c == '\r') {
            out += "\\r";
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\\') {
            out += "\\\\";
        } else if (c >= 0x20 && c < 0x7F) {
            out += static_cast<char>(c);
        } else {
            out += fmt::format("\\x{:02X}", c);
        }
    }
    return out;
}

std::string expected_text(const Exchange& exchange) {
    const auto& cells = exchange.match.expected_cells;
    if (cells.empty()) return exchange.expected;
    const bool ascii = exchange.framing == client::Framing::Ascii;
    std::string out = ascii ? ":" : "";
    for (const auto& c : cells) {
        if (!ascii && !out.empty()) out += ' ';
        out += c;
    }
    if (ascii && cells.back() != kRestCell) out += "\\r\\n";
    return out;
}

std::size_t frame_column(client::Framing framing, std::size_t position) {
    return framing == client::Framing::Ascii ? 1 + position * 2 : position * 3;
}

std::size_t frame_cells(client::Framing framing, std::span<const std::uint8_t> bytes) {
    return framing == client::Framing::Ascii ? frame_bytes(framing, bytes).size() : bytes.size();
}

}  // namespace mblab::conformance
