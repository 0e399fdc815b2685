#include "server/journal_file.hpp"

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>

#include "support/hex_digits.hpp"

namespace mblab::server {

namespace {

constexpr std::size_t kCrcDigits = 8;
constexpr std::string_view kBom = "\xEF\xBB\xBF";

constexpr std::array<std::uint32_t, 256> make_crc_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t n = 0; n < 256; ++n) {
        std::uint32_t c = n;
        for (int k = 0; k < 8; ++k)
            c = (c & 1U) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
        table[n] = c;
    }
    return table;
}

constexpr auto kCrcTable = make_crc_table();

bool blank(std::string_view line) {
    return line.find_first_not_of(" \t") == std::string_view::npos;
}

std::optional<std::uint32_t> hex_number(std::string_view text) {
    if (text.size() != kCrcDigits) return std::nullopt;
    std::uint32_t value = 0;
    for (char c : text) {
        int digit = -1;
        if (c >= '0' && c <= '9') digit = c - '0';
        if (c >= 'A' && c <= 'F') digit = c - 'A' + 10;
        if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
        if (digit < 0) return std::nullopt;
        value = value << 4 | static_cast<std::uint32_t>(digit);
    }
    return value;
}

// One line of a file as read, not yet judged: whether it is the file's last is known only once
// the next line is read.
struct Line {
    std::string text;
    std::size_t number = 0;
    bool torn = false;  // no newline after it
};

class FileReader {
  public:
    FileReader(std::filesystem::path file, const OnRecord& on_record, const OnWarning& on_warning)
        : file_(std::move(file)), on_record_(on_record), on_warning_(on_warning) {}

    bool read(std::string& error) {
        std::error_code ec;
        if (!std::filesystem::exists(file_, ec)) return true;
        std::ifstream in(file_, std::ios::binary);
        if (!in) {
            error = "cannot read the journal " + file_.string() + ": " + std::strerror(errno);
            return false;
        }
        std::optional<Line> pending;
        Line line;
        while (std::getline(in, line.text)) {
            ++line.number;
            line.torn = in.eof();
            if (line.number == 1 && line.text.starts_with(kBom)) line.text.erase(0, kBom.size());
            if (!line.text.empty() && line.text.back() == '\r') line.text.pop_back();
            if (blank(line.text)) continue;
            if (pending && !judge(*pending, false, error)) return false;
            pending = line;
        }
        if (in.bad()) {
            error = "cannot read the journal " + file_.string() + ": " + std::strerror(errno);
            return false;
        }
        return !pending || judge(*pending, true, error);
    }

  private:
    bool judge(const Line& line, bool last, std::string& error) {
        const RecordPlace place{file_, line.number, last};
        const auto star = line.text.rfind('*');
        std::string_view record = line.text;
        std::string problem;
        if (star != std::string::npos) {
            record = record.substr(0, star);
            if (!sealed_) sealed_ = true;
            const auto crc = hex_number(std::string_view(line.text).substr(star + 1));
            if (!crc || *crc != crc32_of(record)) {
                problem = "its checksum does not match (the line was changed or cut short)";
            }
        } else if (!sealed_.value_or(false)) {
            sealed_ = false;
            // Written before records had checksums: nothing says a last line without its
            // newline is whole.
            if (line.torn && last) problem = "it was cut short";
        } else {
            problem = "it has no checksum, as every record of this file has";
        }
        if (problem.empty()) return on_record_(record, place, error);
        if (last) {
            if (on_warning_) {
                on_warning_(
                    "journal " + file_.string() + " line " + std::to_string(line.number) +
                    ": left out, " + problem +
                    "; as the file's last record it was never acknowledged (a crash cut it)");
            }
            return true;
        }
        error = "journal " + file_.string() + " line " + std::to_string(line.number) + ": " +
                problem +
                "; restore the line, or delete it (its write is then lost) and start again";
        return false;
    }

    std::filesystem::path file_;
    const OnRecord& on_record_;
    const OnWarning& on_warning_;
    std::optional<bool> sealed_;
};

}  // namespace

std::uint32_t crc32_of(std::string_view text) {
    std::uint32_t c = 0xFFFFFFFFU;
    for (char ch : text)
        c = kCrcTable[(c ^ static_cast<std::uint8_t>(ch)) & 0xFFU] ^ (c >> 8);
    return c ^ 0xFFFFFFFFU;
}

std::string seal_record(std::string_view record) {
    std::string line(record);
    line += '*';
    const auto crc = crc32_of(record);
    for (int shift = 28; shift >= 0; shift -= 4)
        line += kHexDigits[(crc >> shift) & 0xFU];
    return line;
}

std::filesystem::path journal_old_path(const std::filesystem::path& path) {
    auto old = path;
    old += ".old";
    return old;
}

bool read_journal(const std::filesystem::path& path, const OnRecord& on_record,
                  const OnWarning& on_warning, std::string& error) {
    return FileReader(journal_old_path(path), on_record, on_warning).read(error) &&
           FileReader(path, on_record, on_warning).read(error);
}

}  // namespace mblab::server
