#include "device/register_map_csv.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <vector>

#include "device/number_codec.hpp"
#include "support/hex_digits.hpp"

namespace mblab::device {

namespace {

enum class Cell : std::uint8_t { Text, Number, Integer };

struct Column {
    std::string_view name;
    Cell cell;
};

// The point's own columns come first; the rest are the behaviour's keys, written as given.
constexpr std::array<Column, 19> kColumns = {{{"address", Cell::Integer},
                                              {"bank", Cell::Text},
                                              {"type", Cell::Text},
                                              {"name", Cell::Text},
                                              {"description", Cell::Text},
                                              {"behaviour", Cell::Text},
                                              {"value", Cell::Number},
                                              {"min", Cell::Number},
                                              {"max", Cell::Number},
                                              {"step", Cell::Number},
                                              {"start", Cell::Number},
                                              {"scale", Cell::Number},
                                              {"offset", Cell::Number},
                                              {"period_ms", Cell::Integer},
                                              {"interval_ms", Cell::Integer},
                                              {"lag_ms", Cell::Integer},
                                              {"source", Cell::Integer},
                                              {"source_bank", Cell::Text},
                                              {"order", Cell::Text}}};
constexpr std::size_t kFirstParameter = 6;

constexpr std::array<std::pair<std::string_view, std::string_view>, 8> kBanks = {{
    {"holding_registers", "holding_registers"},
    {"holding", "holding_registers"},
    {"input_registers", "input_registers"},
    {"input", "input_registers"},
    {"coils", "coils"},
    {"coil", "coils"},
    {"discrete_inputs", "discrete_inputs"},
    {"discrete", "discrete_inputs"},
}};

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

std::string trim(std::string_view text) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string_view::npos) return {};
    const auto last = text.find_last_not_of(" \t\r");
    return std::string(text.substr(first, last - first + 1));
}

// One line of RFC 4180 CSV: commas between cells, a cell in double quotes may hold commas and
// "" for a quote. False when a quote is left open.
bool split_cells(std::string_view line, std::vector<std::string>& cells) {
    cells.clear();
    std::string cell;
    bool quoted = false;
    bool was_quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c != '"') {
                cell += c;
            } else if (i + 1 < line.size() && line[i + 1] == '"') {
                cell += '"';
                ++i;
            } else {
                quoted = false;
            }
        } else if (c == '"' && trim(cell).empty()) {
            quoted = was_quoted = true;
            cell.clear();
        } else if (c == ',') {
            cells.push_back(was_quoted ? cell : trim(cell));
            cell.clear();
            was_quoted = false;
        } else {
            cell += c;
        }
    }
    cells.push_back(was_quoted ? cell : trim(cell));
    return !quoted;
}

std::string toml_string(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7F) {
            out += "\\u00";
            out += kHexDigits[u >> 4];
            out += kHexDigits[u & 0xF];
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::optional<std::int64_t> parse_integer(const std::string& text) {
    std::int64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

std::optional<std::string> toml_number(const std::string& text) {
    double value = 0;
    const char* begin = text.data() + (text.starts_with('+') ? 1 : 0);
    const auto [end, ec] = std::from_chars(begin, text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
        return std::nullopt;
    }
    std::array<char, 32> out{};
    const auto written = std::to_chars(out.data(), out.data() + out.size(), value);
    return std::string(out.data(), written.ptr);
}

// The profile text and, for each of its lines, the CSV line it came from (0: none).
class ProfileText {
  public:
    void line(const std::string& text, std::size_t csv_line) {
        text_ += text + "\n";
        origin_.push_back(csv_line);
    }
    const std::string& text() const { return text_; }
    std::size_t origin(std::size_t toml_line) const {
        return toml_line >= 1 && toml_line <= origin_.size() ? origin_[toml_line - 1] : 0;
    }

  private:
    std::string text_;
    std::vector<std::size_t> origin_;
};

struct Point {
    std::size_t line = 0;
    std::string bank;
    std::uint32_t address = 0;
    std::uint32_t width = 1;
    std::vector<std::string> cells;  // by kColumns index, "" when absent
};

class Importer {
  public:
    explicit Importer(const CsvImport& import) : import_(import) {}

    Loaded<ImportedProfile> run(std::string_view csv);

  private:
    std::string fail(std::size_t line, std::string_view column, const std::string& message) {
        return import_.source + ":" + std::to_string(line) + ": " +
               (column.empty() ? "" : std::string(column) + ": ") + message;
    }
    std::optional<std::string> read_header(const std::vector<std::string>& cells, std::size_t line);
    std::optional<std::string> read_point(const std::vector<std::string>& cells, std::size_t line);
    void write_point(const Point& point);
    void write_behaviour(const Point& point);
    std::string locate(const std::string& loader_error) const;

    static std::size_t bank_index(const std::string& bank) {
        const auto it = std::find_if(kBanks.begin(), kBanks.end(),
                                     [&](const auto& b) { return b.second == bank; });
        return static_cast<std::size_t>(it - kBanks.begin()) / 2;
    }

    const CsvImport& import_;
    std::vector<std::size_t> column_of_;  // CSV column -> kColumns index
    std::vector<Point> points_;
    // Per bank (kBanks order, one per pair): 1 + the index in points_ of each address's point,
    // 0 for none; made when the bank's first point comes.
    std::array<std::vector<std::uint32_t>, kBanks.size() / 2> owners_;
    ProfileText out_;
};

std::optional<std::string> Importer::read_header(const std::vector<std::string>& cells,
                                                 std::size_t line) {
    for (const auto& cell : cells) {
        auto name = lower(cell);
        if (name == "behavior") name = "behaviour";
        const auto it = std::find_if(kColumns.begin(), kColumns.end(),
                                     [&](const Column& c) { return c.name == name; });
        if (it == kColumns.end()) {
            std::string names;
            for (const auto& c : kColumns)
                names += (names.empty() ? "" : ", ") + std::string(c.name);
            return fail(line, "", "unknown column \"" + cell + "\"; expected some of " + names);
        }
        const auto index = static_cast<std::size_t>(it - kColumns.begin());
        if (std::find(column_of_.begin(), column_of_.end(), index) != column_of_.end()) {
            return fail(line, "", "column \"" + name + "\" appears twice");
        }
        column_of_.push_back(index);
    }
    if (std::find(column_of_.begin(), column_of_.end(), 0) == column_of_.end()) {
        return fail(line, "",
                    "no address column; the first line names the columns, e.g. "
                    "address,type,name,behaviour,min,max,period_ms");
    }
    return std::nullopt;
}

std::optional<std::string> Importer::read_point(const std::vector<std::string>& cells,
                                                std::size_t line) {
    if (cells.size() > column_of_.size()) {
        return fail(line, "",
                    std::to_string(cells.size()) + " cells, but the header names " +
                        std::to_string(column_of_.size()) + " columns");
    }
    Point point;
    point.line = line;
    point.cells.assign(kColumns.size(), "");
    for (std::size_t i = 0; i < cells.size(); ++i)
        point.cells[column_of_[i]] = cells[i];
    for (std::size_t i = 0; i < kColumns.size(); ++i) {
        const auto& cell = point.cells[i];
        if (cell.empty() || kColumns[i].cell == Cell::Text) continue;
        if (kColumns[i].cell == Cell::Integer ? !parse_integer(cell) : !toml_number(cell)) {
            return fail(line, kColumns[i].name,
                        std::string("expected ") +
                            (kColumns[i].cell == Cell::Integer ? "an integer" : "a number") +
                            ", got \"" + cell + "\"");
        }
    }
    const auto address = parse_integer(point.cells[0]);
    if (!address || *address < 0 || *address > 0xFFFF) {
        return fail(line, "address",
                    "expected an address from 0 to 65535, got \"" + point.cells[0] + "\"");
    }
    point.address = static_cast<std::uint32_t>(*address);
    point.bank = "holding_registers";
    if (const auto& bank = point.cells[1]; !bank.empty()) {
        const auto it = std::find_if(kBanks.begin(), kBanks.end(),
                                     [&](const auto& b) { return b.first == lower(bank); });
        if (it == kBanks.end()) {
            return fail(line, "bank",
                        "expected one of holding, input, coil, discrete, got \"" + bank + "\"");
        }
        point.bank = std::string(it->second);
    }
    const bool bits = point.bank == "coils" || point.bank == "discrete_inputs";
    if (auto& type = point.cells[2]; !type.empty()) {
        type = lower(type);
        const auto known = register_type_named(type);
        if (bits && type != "bit") {
            return fail(line, "type", "a " + point.bank + " point is a bit, got \"" + type + "\"");
        }
        if (!bits && !known) {
            return fail(line, "type",
                        "expected one of " + register_type_names() + ", got \"" + type + "\"");
        }
        if (!bits) point.width = number_width(*known);
    }
    if (point.address + point.width > 0x10000) {
        return fail(
            line, "address",
            "a " + point.cells[2] + " at " + point.cells[0] + " would end past address 65535");
    }
    if (point.cells[5].empty()) {
        for (std::size_t i = kFirstParameter; i < kColumns.size(); ++i) {
            if (!point.cells[i].empty()) {
                return fail(line, kColumns[i].name,
                            "a behaviour parameter without a behaviour; give the behaviour "
                            "column, e.g. sine");
            }
        }
    }
    // Each address knows the point that holds it: a scan of every earlier point made a map of
    // the whole address space (4 x 65536 rows) take minutes.
    auto& owners = owners_[bank_index(point.bank)];
    if (owners.empty()) owners.assign(0x10000, 0);
    std::uint32_t first_owner = 0;
    for (std::uint32_t a = point.address; a < point.address + point.width; ++a) {
        if (owners[a] != 0 && (first_owner == 0 || owners[a] < first_owner))
            first_owner = owners[a];
    }
    if (first_owner != 0) {
        const auto& other = points_[first_owner - 1];
        return fail(line, "address",
                    point.bank + " " + std::to_string(point.address) + " overlaps line " +
                        std::to_string(other.line) + " (" + std::to_string(other.address) + ".." +
                        std::to_string(other.address + other.width - 1) + ")");
    }
    points_.push_back(std::move(point));
    const auto& placed = points_.back();
    for (std::uint32_t a = placed.address; a < placed.address + placed.width; ++a)
        owners[a] = static_cast<std::uint32_t>(points_.size());
    return std::nullopt;
}

void Importer::write_point(const Point& point) {
    const auto line = point.line;
    out_.line("", 0);
    out_.line("[[unit." + point.bank + "]]", line);
    out_.line("start = " + std::to_string(point.address), line);
    out_.line("count = " + std::to_string(point.width), line);
    // Ranges know u16, i16, u32 and f32; other types are their registers.
    const auto& type = point.cells[2];
    if (type == "i16" || type == "u32" || type == "f32") out_.line("type = \"" + type + "\"", line);
    if (!point.cells[3].empty()) out_.line("name = " + toml_string(point.cells[3]), line);
    if (!point.cells[4].empty()) out_.line("description = " + toml_string(point.cells[4]), line);
}

void Importer::write_behaviour(const Point& point) {
    const auto line = point.line;
    out_.line("", 0);
    out_.line("[[unit.behaviours]]", line);
    out_.line("kind = " + toml_string(lower(point.cells[5])), line);
    out_.line("bank = \"" + point.bank + "\"", line);
    out_.line("address = " + std::to_string(point.address), line);
    if (!point.cells[2].empty() && point.cells[2] != "bit") {
        out_.line("type = \"" + point.cells[2] + "\"", line);
    }
    for (std::size_t i = kFirstParameter; i < kColumns.size(); ++i) {
        const auto& cell = point.cells[i];
        if (cell.empty()) continue;
        const auto value = kColumns[i].cell == Cell::Text     ? toml_string(cell)
                           : kColumns[i].cell == Cell::Number ? *toml_number(cell)
                                                              : cell;
        out_.line(std::string(kColumns[i].name) + " = " + value, line);
    }
}

// The loader's "SOURCE:LINE: unit[0].behaviours[2].max: why" as "FILE.csv:LINE: max: why".
std::string Importer::locate(const std::string& loader_error) const {
    const std::string prefix = import_.source + ".toml:";
    if (!loader_error.starts_with(prefix)) return loader_error;
    std::size_t at = prefix.size();
    std::size_t toml_line = 0;
    while (at < loader_error.size() && std::isdigit(static_cast<unsigned char>(loader_error[at])))
        toml_line = toml_line * 10 + static_cast<std::size_t>(loader_error[at++] - '0');
    std::string rest = loader_error.substr(std::min(at + 2, loader_error.size()));
    const auto path_end = rest.find(": ");
    if (path_end != std::string::npos) {
        const auto key = rest.rfind('.', path_end);
        if (key != std::string::npos) rest = rest.substr(key + 1);
    }
    const auto csv_line = out_.origin(toml_line);
    return import_.source + ":" + (csv_line ? std::to_string(csv_line) + ": " : "") + rest;
}

Loaded<ImportedProfile> Importer::run(std::string_view csv) {
    // A spreadsheet saving "CSV UTF-8" starts the file with a byte order mark; it is not part of
    // the first column's name.
    constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
    if (csv.starts_with(kByteOrderMark)) csv.remove_prefix(kByteOrderMark.size());
    std::vector<std::string> cells;
    std::size_t line = 0;
    bool header = false;
    while (!csv.empty()) {
        // Lines end in LF, CRLF or, from old Mac spreadsheets, a lone CR.
        const auto end = csv.find_first_of("\r\n");
        const auto text = csv.substr(0, end);
        std::size_t next = end == std::string_view::npos ? csv.size() : end + 1;
        if (end != std::string_view::npos && csv[end] == '\r' && next < csv.size() &&
            csv[next] == '\n')
            ++next;
        csv.remove_prefix(next);
        ++line;
        if (trim(text).empty() || trim(text).starts_with('#')) continue;
        if (!split_cells(text, cells)) return fail(line, "", "a quoted cell is not closed");
        const auto error = header ? read_point(cells, line) : read_header(cells, line);
        if (error) return *error;
        header = true;
    }
    if (points_.empty()) {
        return fail(line, "", "no points; after the header line, give one point per line");
    }
    out_.line("# Imported by mblab profile import-csv from " + import_.source + ".", 0);
    out_.line("name = " + toml_string(import_.name), 0);
    out_.line("", 0);
    out_.line("[[unit]]", 0);
    out_.line("id = " + std::to_string(import_.unit), 0);
    for (const auto& point : points_)
        write_point(point);
    for (const auto& point : points_) {
        if (!point.cells[5].empty()) write_behaviour(point);
    }
    auto loaded = parse_profile(out_.text(), import_.source + ".toml");
    if (!loaded) return locate(loaded.error());
    return ImportedProfile{out_.text()};
}

}  // namespace

Loaded<ImportedProfile> register_map_to_profile(std::string_view csv, const CsvImport& import) {
    return Importer(import).run(csv);
}

}  // namespace mblab::device
