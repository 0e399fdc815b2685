#include "server/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "server/file_writes.hpp"
#include "server/journal_file.hpp"

namespace mblab::server {

namespace {

constexpr std::size_t kCopyChunk = 64 * 1024;

int open_new(const std::filesystem::path& path) {
    return ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC | O_NOFOLLOW,
                  0600);
}

// Appends the whole of `from` to `to`; false at the first read or write that fails.
bool copy_all(int from, int to) {
    std::string chunk(kCopyChunk, '\0');
    for (;;) {
        auto n = ::read(from, chunk.data(), chunk.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return false;
        if (n == 0) return true;
        if (!write_all(to, std::string_view(chunk.data(), static_cast<std::size_t>(n)))) {
            return false;
        }
    }
}

off_t size_of(int fd) {
    struct stat st {};
    return ::fstat(fd, &st) == 0 ? st.st_size : -1;
}

}  // namespace

protocol::Result<std::unique_ptr<Journal>, std::string> Journal::create(
    const std::filesystem::path& path) {
    int fd = open_new(path);
    if (fd < 0) return "cannot create the journal " + path.string() + ": " + std::strerror(errno);
    sync_directory_of(path);
    return std::unique_ptr<Journal>(new Journal(path, fd));
}

Journal::Journal(std::filesystem::path path, int fd)
    : path_(std::move(path)), old_path_(journal_old_path(path_)), fd_(fd) {
    std::error_code ec;
    old_exists_ = std::filesystem::exists(old_path_, ec);
    worker_.start([this] { return !queue_.empty(); },
                  [this](WorkThread::Lock& lock) { write_queued(lock); });
}

Journal::~Journal() {
    worker_.stop();
    if (fd_ >= 0) ::close(fd_);
}

void Journal::append(std::string record, Durable done) {
    push({Item::Kind::Record, std::move(record), std::move(done)});
}

std::uint64_t Journal::rotate() {
    const auto rotation = ++rotations_;
    push({Item::Kind::Rotate, {}, {}, rotation});
    return rotation;
}

void Journal::drop_old(std::uint64_t rotation) {
    push({Item::Kind::DropOld, {}, {}, rotation});
}

std::uint64_t Journal::syncs() const {
    std::lock_guard lock(worker_.mutex());
    return syncs_;
}

void Journal::push(Item item) {
    {
        std::lock_guard lock(worker_.mutex());
        queue_.push_back(std::move(item));
    }
    worker_.wake();
}

// Writes what was queued, the records made durable together: one fdatasync for a batch.
void Journal::write_queued(WorkThread::Lock& lock) {
    batch_.swap(queue_);
    lock.unlock();
    for (auto& item : batch_) {
        switch (item.kind) {
            case Item::Kind::Record:
                buffer_ += seal_record(item.record);
                buffer_ += '\n';
                waiting_.push_back(std::move(item.done));
                break;
            case Item::Kind::Rotate:
                flush();
                (void)do_rotate();
                last_rotation_ = item.rotation;
                break;
            case Item::Kind::DropOld:
                // Records appended after the rotation may be in PATH.old when a rotation
                // failed half-way: then it never goes.
                if (item.rotation != last_rotation_ || appending_to_old_) break;
                flush();
                if (::unlink(old_path_.c_str()) == 0 || errno == ENOENT) {
                    old_exists_ = false;
                    sync_directory_of(path_);
                }
                break;
        }
    }
    batch_.clear();
    flush();
    lock.lock();
}

void Journal::flush() {
    if (waiting_.empty()) return;
    bool written = fd_ >= 0 && (!torn_ || ::ftruncate(fd_, good_size_) == 0);
    if (written) torn_ = false;
    written = written && write_all(fd_, buffer_) && ::fdatasync(fd_) == 0;
    if (written) {
        good_size_ += static_cast<off_t>(buffer_.size());
    } else if (fd_ >= 0) {
        // A record cut short by a full disk would glue the next one to it: the file goes back
        // to its last good end, and until it does nothing more is appended.
        torn_ = ::ftruncate(fd_, good_size_) != 0;
    }
    {
        std::lock_guard lock(worker_.mutex());
        ++syncs_;
    }
    for (auto& done : waiting_) {
        if (done) done(written);
    }
    buffer_.clear();
    waiting_.clear();
}

// Every step is checked; on a failure the records stay where replay finds them (PATH.old, then
// PATH) and nothing is truncated or removed. A rotation that did not happen costs nothing but
// a longer replay: the save that follows covers PATH.old, and PATH's records set values the
// state already holds.
bool Journal::do_rotate() {
    if (fd_ < 0 || torn_) return false;
    if (old_exists_) {
        // The last save failed (or is still running), so PATH.old holds records no state file
        // has: keep them, with these after them.
        int in = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
        int old = ::open(old_path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
        const off_t old_size = old >= 0 ? size_of(old) : -1;
        const bool copied = in >= 0 && old_size >= 0 && copy_all(in, old) && ::fdatasync(old) == 0;
        if (!copied && old_size >= 0 && ::ftruncate(old, old_size) == 0) ::fdatasync(old);
        if (in >= 0) ::close(in);
        if (old >= 0) ::close(old);
        if (!copied) return false;
        // Should this fail, the records are in both files, which replay takes twice harmlessly.
        if (::ftruncate(fd_, 0) != 0) return false;
        good_size_ = 0;
        ::fdatasync(fd_);
        return true;
    }
    if (::rename(path_.c_str(), old_path_.c_str()) != 0) return false;
    int fd = open_new(path_);
    if (fd < 0) {
        // Back where replay finds them last; should that fail too, the open descriptor writes
        // to PATH.old, which replay reads first, and no PATH follows it.
        if (::rename(old_path_.c_str(), path_.c_str()) != 0) {
            old_exists_ = true;
            appending_to_old_ = true;
        }
        return false;
    }
    ::close(fd_);
    fd_ = fd;
    good_size_ = 0;
    old_exists_ = true;
    sync_directory_of(path_);
    return true;
}

void remove_journal(const std::filesystem::path& path) {
    ::unlink(path.c_str());
    ::unlink(journal_old_path(path).c_str());
    sync_directory_of(path);
}

}  // namespace mblab::server
