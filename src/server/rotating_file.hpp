#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "protocol/result.hpp"

// A log file that never grows past its limit: a line that would take FILE past `max_size` first
// moves FILE to FILE.1 (replacing the one before), so at most two limits' worth stays on disk.
// A write the disk refuses (ENOSPC) drops the line and says so once, through `warn`, until a
// write works again; it never stops the caller.
namespace mblab::server {

class RotatingFile {
  public:
    using Warn = std::function<void(const std::string& warning)>;

    // Opens FILE for appending (made when missing); an error names the file when it cannot.
    static protocol::Result<RotatingFile, std::string> open(const std::filesystem::path& path,
                                                            std::uint64_t max_size, Warn warn);
    // Lines to an open descriptor (standard error) that is never rotated nor closed.
    static RotatingFile unrotated(int fd, std::string name, Warn warn);

    RotatingFile(RotatingFile&& other) noexcept;
    RotatingFile& operator=(RotatingFile&&) = delete;
    RotatingFile(const RotatingFile&) = delete;
    ~RotatingFile();

    // `line` without its newline; false when it was dropped.
    bool write_line(std::string_view line);
    std::uint64_t size() const { return size_; }

  private:
    RotatingFile(int fd, std::filesystem::path path, std::uint64_t max_size, bool owned, Warn warn);
    bool rotate();
    void failed(const std::string& what);

    int fd_ = -1;
    std::filesystem::path path_;
    std::uint64_t max_size_ = 0;  // 0: never rotated
    std::uint64_t size_ = 0;
    bool owned_ = true;
    bool warned_ = false;  // a failure was told and no write has worked since
    Warn warn_;
};

std::filesystem::path rotated_path(const std::filesystem::path& path);

}  // namespace mblab::server
