#include "server/file_writes.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

namespace mblab::server {

bool write_all(int fd, std::string_view text) {
    while (!text.empty()) {
        auto n = ::write(fd, text.data(), text.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        text.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
}

void sync_directory_of(const std::filesystem::path& path) {
    auto directory = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

}  // namespace mblab::server
