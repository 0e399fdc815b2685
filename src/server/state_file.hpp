#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

// The file that keeps a device's writable data across restarts (`mblab serve --state FILE`).
namespace mblab::server {

// Replaces `path` so that a crash at any moment leaves either the old or the new text, never a
// mix: write a new temporary file of a unique name beside it (mode 0600, or the mode `path`
// has), fsync it, rename it over `path`, fsync the directory.
bool write_file_atomically(const std::filesystem::path& path, std::string_view text,
                           std::string& error);

// Whether a file can be created beside `path`, as each save does: a missing or read-only
// directory is found at start rather than at the first save.
bool check_state_writable(const std::filesystem::path& path, std::string& error);

// The whole file; nullopt with an empty `error` when it does not exist (a first start).
std::optional<std::string> read_state_file(const std::filesystem::path& path, std::string& error);

}  // namespace mblab::server
