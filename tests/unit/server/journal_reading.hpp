#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "server/journal.hpp"

// A whole journal file read back the way replay reads it, for the journal tests.
namespace mblab::server {

struct JournalRead {
    bool ok = false;
    std::vector<std::string> records;
    std::vector<std::size_t> lines;  // the line each record starts on
    std::vector<std::string> warnings;
    std::string error;
};

inline JournalRead read_all(const std::filesystem::path& path) {
    JournalRead out;
    out.ok = read_journal(
        path,
        [&](std::string_view record, const RecordPlace& place, std::string&) {
            out.records.emplace_back(record);
            out.lines.push_back(place.line);
            return true;
        },
        [&](const std::string& warning) { out.warnings.push_back(warning); }, out.error);
    return out;
}

}  // namespace mblab::server
