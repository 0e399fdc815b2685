#include "conformance/evidence_text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <optional>

#include "client/hex_text.hpp"
#include "conformance/line_evidence.hpp"

namespace mblab::conformance {

namespace {

constexpr std::size_t kLabelWidth = 10;  // "received  "

// One cell of a line, or a run of equal cells as "5A x246".
std::string cell_text(const std::string& cell, std::size_t count) {
    return count == 1 ? cell : fmt::format("{} x{}", cell, count);
}

// `cells` joined by spaces, each run of kShortestRun or more equal cells as one.
std::string compact_cells(const std::vector<std::string>& cells) {
    std::string out;
    for (std::size_t i = 0; i < cells.size();) {
        std::size_t run = 1;
        while (i + run < cells.size() && cells[i + run] == cells[i])
            ++run;
        if (run < kShortestRun) run = 1;
        if (!out.empty()) out += ' ';
        out += cell_text(cells[i], run);
        i += run;
    }
    return out;
}

std::vector<std::string> byte_cells(std::span<const std::uint8_t> bytes) {
    std::vector<std::string> cells;
    cells.reserve(bytes.size());
    for (std::uint8_t byte : bytes)
        cells.push_back(fmt::format("{:02X}", byte));
    return cells;
}

std::string received_text(const Exchange& exchange, std::string bytes) {
    std::string why;
    switch (exchange.status) {
        case client::ReceiveStatus::Frame:
            return bytes;
        case client::ReceiveStatus::Timeout:
            if (exchange.silence_expected) return bytes.empty() ? "nothing" : bytes;
            why = fmt::format("timeout after {} ms", exchange.waited.count());
            break;
        case client::ReceiveStatus::Closed:
        case client::ReceiveStatus::Malformed:
            why = exchange.detail;
            break;
    }
    return bytes.empty() ? why : fmt::format("{}  ({})", bytes, why);
}

// The received and expected lines of a frame compared byte by byte, cell for cell: a run is
// compacted only where both lines repeat one cell and its bytes all differ or all match, so both
// lines (and the ^^ line) keep the same columns.
struct Compared {
    EvidenceLine received;
    EvidenceLine expected;
    std::string marks;
};

Compared compare(const Exchange& exchange) {
    const auto got = byte_cells(exchange.received);
    const auto& want = exchange.match.expected_cells;
    const auto& differs = exchange.match.differs;
    const std::size_t total = std::max(got.size(), want.size());
    const auto differs_at = [&](std::size_t i) {
        return std::find(differs.begin(), differs.end(), i) != differs.end();
    };
    const auto same = [&](std::size_t a, std::size_t b) {
        return (a < got.size()) == (b < got.size()) && (a >= got.size() || got[a] == got[b]) &&
               (a < want.size()) == (b < want.size()) && (a >= want.size() || want[a] == want[b]) &&
               differs_at(a) == differs_at(b);
    };
    Compared out;
    std::string received;
    std::string expected;
    for (std::size_t i = 0; i < total;) {
        std::size_t run = 1;
        while (i + run < total && same(i, i + run))
            ++run;
        if (run < kShortestRun) run = 1;
        const std::string got_text = i < got.size() ? cell_text(got[i], run) : std::string();
        const std::string want_text = i < want.size() ? cell_text(want[i], run) : std::string();
        const std::size_t column = i == 0 ? 0 : std::max(received.size(), expected.size()) + 1;
        const std::size_t width = std::max(got_text.size(), want_text.size());
        for (auto* line : {&received, &expected}) {
            const std::string& text = line == &received ? got_text : want_text;
            if (text.empty()) continue;
            line->resize(column, ' ');
            *line += text;
        }
        if (differs_at(i)) {
            const std::pair<std::size_t, std::size_t> span{kLabelWidth + column,
                                                           kLabelWidth + column + width};
            if (!got_text.empty()) out.received.marked.push_back(span);
            if (!want_text.empty()) out.expected.marked.push_back(span);
            out.marks.resize(column + width, ' ');
            std::fill(out.marks.begin() + static_cast<std::ptrdiff_t>(column), out.marks.end(),
                      '^');
        }
        i += run;
    }
    out.received.text = received;
    out.expected.text = expected;
    return out;
}

// An ASCII frame is shown as its text (line_evidence.hpp), two characters per byte after the
// ':', so runs are not compacted and the marks fall where frame_column puts each byte.
std::vector<EvidenceLine> ascii_layout(const Exchange& exchange) {
    const auto framing = exchange.framing;
    std::vector<EvidenceLine> lines;
    lines.push_back({"sent      " + frame_text(framing, exchange.sent)});
    EvidenceLine received{"received  " +
                          received_text(exchange, frame_text(framing, exchange.received))};
    if (exchange.silence_expected) {
        lines.push_back(std::move(received));
        lines.push_back({"expected  nothing"});
        return lines;
    }
    EvidenceLine expected{"expected  " + expected_text(exchange)};
    std::string marks;
    if (!exchange.received.empty()) {
        const std::size_t got = frame_cells(framing, exchange.received);
        const std::size_t want = exchange.match.expected_cells.size();
        for (std::size_t position : exchange.match.differs) {
            const std::size_t column = frame_column(framing, position);
            const std::pair<std::size_t, std::size_t> span{kLabelWidth + column,
                                                           kLabelWidth + column + 2};
            if (position < got) received.marked.push_back(span);
            if (position < want) expected.marked.push_back(span);
            if (marks.size() < column + 2) marks.resize(column + 2, ' ');
            marks[column] = marks[column + 1] = '^';
        }
    }
    lines.push_back(std::move(received));
    lines.push_back(std::move(expected));
    if (!marks.empty()) lines.push_back({std::string(kLabelWidth, ' ') + marks});
    return lines;
}

}  // namespace

std::string compact_hex(std::span<const std::uint8_t> bytes) {
    return compact_cells(byte_cells(bytes));
}

std::vector<EvidenceLine> evidence_layout(const Exchange& exchange) {
    if (exchange.framing == client::Framing::Ascii) return ascii_layout(exchange);
    std::vector<EvidenceLine> lines;
    lines.push_back({"sent      " + compact_hex(exchange.sent)});
    if (exchange.silence_expected) {
        lines.push_back({"received  " + received_text(exchange, compact_hex(exchange.received))});
        lines.push_back({"expected  nothing"});
        return lines;
    }
    const auto& cells = exchange.match.expected_cells;
    // Only a received frame can be compared byte by byte.
    if (exchange.received.empty() || exchange.match.differs.empty()) {
        lines.push_back({"received  " + received_text(exchange, compact_hex(exchange.received))});
        lines.push_back(
            {"expected  " + (cells.empty() ? exchange.expected : compact_cells(cells))});
        return lines;
    }
    Compared compared = compare(exchange);
    compared.received.text = "received  " + received_text(exchange, compared.received.text);
    compared.expected.text = "expected  " + compared.expected.text;
    lines.push_back(std::move(compared.received));
    lines.push_back(std::move(compared.expected));
    lines.push_back({std::string(kLabelWidth, ' ') + compared.marks});
    return lines;
}

std::vector<std::string> evidence_lines(const Exchange& exchange) {
    std::vector<std::string> out;
    for (auto& line : evidence_layout(exchange))
        out.push_back(std::move(line.text));
    return out;
}

namespace {

// Where a piece of `group` that starts at column `start` ends, at most at `limit`: a column
// where every line of the group has a space or has ended, so no cell is cut, and the next piece
// starts past that space; at `limit` itself when there is none.
std::pair<std::size_t, std::size_t> cut_at(const std::vector<const std::string*>& group,
                                           std::size_t start, std::size_t limit) {
    for (std::size_t column = limit; column > start; --column) {
        const bool between = std::all_of(group.begin(), group.end(), [&](const std::string* line) {
            return column >= line->size() || (*line)[column] == ' ';
        });
        if (between) return {column, column + 1};
    }
    return {limit, limit};
}

// Cuts `group` into pieces of at most `width` columns, appended to `out`. A piece after the
// first of a lone line is indented; a group's lines each keep their label, so every piece of the
// bytes says whether it was received or expected.
void wrap_group(const std::vector<const std::string*>& group, std::size_t width,
                std::vector<std::string>& out) {
    std::size_t longest = 0;
    for (const auto* line : group)
        longest = std::max(longest, line->size());
    // A terminal too narrow for a few cells still gets a few cells a line.
    const std::size_t room = std::max(width, kLabelWidth + 24) - kLabelWidth;
    if (longest <= kLabelWidth + room) {
        for (const auto* line : group)
            out.push_back(*line);
        return;
    }
    for (std::size_t start = kLabelWidth; start < longest;) {
        const auto [end, next] = longest <= start + room ? std::pair{longest, longest}
                                                         : cut_at(group, start, start + room);
        for (const auto* line : group) {
            if (start >= line->size()) continue;
            std::string piece = line->substr(start, end - start);
            piece.erase(piece.find_last_not_of(' ') + 1);
            if (piece.empty()) continue;
            const bool labelled = start == kLabelWidth || group.size() > 1;
            out.push_back(
                (labelled ? line->substr(0, kLabelWidth) : std::string(kLabelWidth, ' ')) + piece);
        }
        start = next;
    }
}

}  // namespace

std::vector<std::string> wrap_evidence(const std::vector<std::string>& lines, std::size_t width) {
    if (width == 0) return lines;
    std::vector<std::string> out;
    // A compared frame ends in the ^^ line: it and the two lines above it are cut together.
    const bool compared =
        lines.size() >= 4 && lines.back().starts_with(std::string(kLabelWidth, ' '));
    const std::size_t alone = compared ? lines.size() - 3 : lines.size();
    for (std::size_t i = 0; i < alone; ++i)
        wrap_group({&lines[i]}, width, out);
    if (compared) wrap_group({&lines[alone], &lines[alone + 1], &lines[alone + 2]}, width, out);
    return out;
}

std::string format_duration(std::chrono::microseconds elapsed) {
    const double seconds = static_cast<double>(elapsed.count()) / 1e6;
    if (seconds >= 0.1) return fmt::format("{:.2f} s", seconds);
    return fmt::format("{:.1f} ms", seconds * 1e3);
}

std::string describe_dut(const Dut& dut) {
    auto yes_no = [](bool value) { return value ? "yes" : "no"; };
    std::string registers =
        dut.registers ? fmt::format("{} registers", *dut.registers) : "registers not declared";
    return fmt::format("unit {}, {}, max read {}, object messaging: {}, alternate encoding: {}",
                       dut.unit, registers, dut.max_read, yes_no(dut.object_messaging),
                       yes_no(dut.alternate_encoding));
}

}  // namespace mblab::conformance
