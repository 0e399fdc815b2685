#include "server/rotating_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

namespace mblab::server {

namespace {

int open_append(const std::filesystem::path& path, int extra) {
    return ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | extra, 0644);
}

}  // namespace

std::filesystem::path rotated_path(const std::filesystem::path& path) {
    return std::filesystem::path(path.string() + ".1");
}

protocol::Result<RotatingFile, std::string> RotatingFile::open(const std::filesystem::path& path,
                                                               std::uint64_t max_size, Warn warn) {
    const int fd = open_append(path, 0);
    if (fd < 0) return std::string(path.string() + ": " + std::strerror(errno));
    RotatingFile file(fd, path, max_size, true, std::move(warn));
    struct stat st {};
    if (::fstat(fd, &st) == 0) file.size_ = static_cast<std::uint64_t>(st.st_size);
    return file;
}

RotatingFile RotatingFile::unrotated(int fd, std::string name, Warn warn) {
    return RotatingFile(fd, std::move(name), 0, false, std::move(warn));
}

RotatingFile::RotatingFile(int fd, std::filesystem::path path, std::uint64_t max_size, bool owned,
                           Warn warn)
    : fd_(fd), path_(std::move(path)), max_size_(max_size), owned_(owned), warn_(std::move(warn)) {}

RotatingFile::RotatingFile(RotatingFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      max_size_(other.max_size_),
      size_(other.size_),
      owned_(other.owned_),
      warned_(other.warned_),
      warn_(std::move(other.warn_)) {}

RotatingFile::~RotatingFile() {
    if (owned_ && fd_ >= 0) ::close(fd_);
}

void RotatingFile::failed(const std::string& what) {
    if (warned_) return;
    warned_ = true;
    if (warn_) warn_(path_.string() + ": " + what + "; log lines are dropped until it works again");
}

bool RotatingFile::rotate() {
    if (::rename(path_.c_str(), rotated_path(path_).c_str()) != 0) {
        // Kept in place rather than grown: the limit is what protects the disk.
        failed(std::string("cannot move it to ") + rotated_path(path_).string() + ": " +
               std::strerror(errno) + "; it starts again empty");
        if (::ftruncate(fd_, 0) != 0) return false;
        size_ = 0;
        return true;
    }
    const int fd = open_append(path_, O_TRUNC);
    if (fd < 0) {
        failed(std::string("cannot open it again: ") + std::strerror(errno));
        return false;
    }
    ::close(fd_);
    fd_ = fd;
    size_ = 0;
    return true;
}

bool RotatingFile::write_line(std::string_view line) {
    if (fd_ < 0) return false;
    std::string text(line);
    text += '\n';
    if (max_size_ > 0 && size_ > 0 && size_ + text.size() > max_size_ && !rotate()) return false;
    std::size_t done = 0;
    while (done < text.size()) {
        const auto n = ::write(fd_, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            failed(std::string("cannot write: ") + std::strerror(n < 0 ? errno : ENOSPC));
            // A torn line is cut off again so the next one starts a line of its own.
            if (done > 0 && owned_ && ::ftruncate(fd_, static_cast<off_t>(size_)) != 0) {
                size_ += done;
            }
            return false;
        }
        done += static_cast<std::size_t>(n);
    }
    size_ += text.size();
    warned_ = false;
    return true;
}

}  // namespace mblab::server
