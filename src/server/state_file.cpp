#include "server/state_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "server/file_writes.hpp"

namespace mblab::server {

namespace {

std::string errno_text(const std::string& what, const std::filesystem::path& path) {
    return what + " " + path.string() + ": " + std::strerror(errno);
}

// A new file beside `path`. A fixed name such as FILE.tmp opened with O_CREAT would follow a
// symlink planted there and overwrite its target. mkostemp() makes a new file of a name nobody
// could guess (it fails rather than open anything that exists), with mode 0600.
int create_temporary(const std::filesystem::path& path, std::filesystem::path& temporary,
                     std::string& error) {
    auto pattern = path;
    pattern += ".XXXXXX";
    std::string name = pattern.string();
    int fd = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd < 0) {
        error = errno_text("cannot create a temporary file for", path);
        return -1;
    }
    temporary = name;
    return fd;
}

}  // namespace

bool check_state_writable(const std::filesystem::path& path, std::string& error) {
    std::filesystem::path temporary;
    int fd = create_temporary(path, temporary, error);
    if (fd < 0) return false;
    ::close(fd);
    ::unlink(temporary.c_str());
    return true;
}

bool write_file_atomically(const std::filesystem::path& path, std::string_view text,
                           std::string& error) {
    // rename() replaces FILE itself, never what a link at FILE points to.
    std::filesystem::path temporary;
    int fd = create_temporary(path, temporary, error);
    if (fd < 0) return false;
    // The file keeps its mode across saves, so a user's chmod is not undone by the next save.
    struct stat old {};
    if (::stat(path.c_str(), &old) == 0 && S_ISREG(old.st_mode)) {
        ::fchmod(fd, old.st_mode & 07777);
    }
    bool written = write_all(fd, text) && ::fsync(fd) == 0;
    if (!written) error = errno_text("cannot write", temporary);
    ::close(fd);
    if (!written) {
        ::unlink(temporary.c_str());
        return false;
    }
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        error = errno_text("cannot replace", path);
        ::unlink(temporary.c_str());
        return false;
    }
    sync_directory_of(path);
    return true;
}

std::optional<std::string> read_state_file(const std::filesystem::path& path, std::string& error) {
    error.clear();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    if (!std::filesystem::is_regular_file(path, ec)) {
        error = "cannot read " + path.string() + ": not a regular file";
        return std::nullopt;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = errno_text("cannot read", path);
        return std::nullopt;
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace mblab::server
