#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

// The text of a journal file (server/journal.hpp writes it). One record a line, sealed with the
// CRC-32 of its text: "RECORD*CRC" (CRC as 8 upper-case hex digits), so that a changed digit is
// found rather than replayed as a wrong value. Journals written before the checksum (lines
// without '*') are still read, a file at a time: once a file's first record has a checksum,
// every record of that file needs one.
namespace mblab::server {

std::uint32_t crc32_of(std::string_view text);
// "RECORD*CRC", without the newline.
std::string seal_record(std::string_view record);

// Where a record came from, for messages that let someone find it.
struct RecordPlace {
    std::filesystem::path file;
    std::size_t line = 0;  // from 1
    bool last = false;     // the file's last record: one a crash may have cut
};

// Called for each good record in order; false stops the reading (with the error it sets).
using OnRecord =
    std::function<bool(std::string_view record, const RecordPlace& place, std::string& error)>;
// Told about a record left out that was never acknowledged (a torn last line).
using OnWarning = std::function<void(const std::string& warning)>;

// Reads PATH.old's records, then PATH's, a line at a time (memory stays flat whatever the
// size). A UTF-8 BOM, CRLF line ends and blank lines, as an editor may leave them, are taken.
// The last line of a file may be torn by a crash (no newline, or a checksum that fails): it was
// never acknowledged, so it is left out with a warning. A bad record anywhere else stops the
// reading with one line naming the file, the line and what to do. Missing files hold nothing.
bool read_journal(const std::filesystem::path& path, const OnRecord& on_record,
                  const OnWarning& on_warning, std::string& error);

std::filesystem::path journal_old_path(const std::filesystem::path& path);

}  // namespace mblab::server
