#pragma once

#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "support/temp_dir.hpp"

// A tmpfs of a few kilobytes, to run out of disk space on purpose. Mounting needs root; it is
// done in a mount namespace of the test process's own (made private), so nothing outside sees
// it and nothing is left mounted if the test dies. Children (`mblab serve`) share it.
namespace mblab::test {

class SmallTmpfs {
  public:
    explicit SmallTmpfs(const std::string& size) {
        if (::geteuid() != 0) {
            why_not_ = "mounting a tmpfs needs root";
            return;
        }
        static const bool own_namespace =
            ::unshare(CLONE_NEWNS) == 0 &&
            ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) == 0;
        if (!own_namespace) {
            why_not_ = std::string("no mount namespace of our own: ") + std::strerror(errno);
            return;
        }
        const auto options = "size=" + size;
        if (::mount("tmpfs", dir_.path().c_str(), "tmpfs", 0, options.c_str()) != 0) {
            why_not_ = std::string("cannot mount a tmpfs: ") + std::strerror(errno);
            return;
        }
        mounted_ = true;
    }
    ~SmallTmpfs() {
        if (mounted_) ::umount2(dir_.path().c_str(), MNT_DETACH);
    }
    SmallTmpfs(const SmallTmpfs&) = delete;
    SmallTmpfs& operator=(const SmallTmpfs&) = delete;

    bool mounted() const { return mounted_; }
    const std::string& why_not() const { return why_not_; }
    std::filesystem::path operator/(const std::string& name) const { return dir_ / name; }

    // Fills the free space with FILL (the disk is then full); the bytes written.
    std::size_t fill() const {
        const auto path = dir_ / "FILL";
        int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
        if (fd < 0) return 0;
        std::size_t total = 0;
        const std::string chunk(512, 'x');
        for (std::size_t size = chunk.size(); size > 0;) {
            const auto n = ::write(fd, chunk.data(), size);
            if (n > 0) {
                total += static_cast<std::size_t>(n);
            } else {
                size /= 2;  // the last page's room, to the byte
            }
        }
        ::close(fd);
        return total;
    }
    // Gives the space FILL took back.
    void free_space() const { std::filesystem::remove(dir_ / "FILL"); }
    // Makes the file system bigger (or smaller), as a disk that gets room again.
    bool resize(const std::string& size) const {
        const auto options = "size=" + size;
        return ::mount(nullptr, dir_.path().c_str(), nullptr, MS_REMOUNT, options.c_str()) == 0;
    }

  private:
    TempDir dir_;
    bool mounted_ = false;
    std::string why_not_;
};

}  // namespace mblab::test
