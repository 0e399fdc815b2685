#pragma once

#include <filesystem>
#include <string_view>

// What the state file and the journal need to put bytes on disk for good.
namespace mblab::server {

// Writes all of `text`, retrying short writes and EINTR; false on an error (errno says which).
bool write_all(int fd, std::string_view text);
// A file created, renamed or removed in a directory is durable only once the directory is.
void sync_directory_of(const std::filesystem::path& path);

}  // namespace mblab::server
