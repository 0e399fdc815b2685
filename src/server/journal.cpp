#include "server/journal.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "server/file_writes.hpp"

namespace mblab::server {

namespace {

std::filesystem::path old_path_of(const std::filesystem::path& path) {
    auto old = path;
    old += ".old";
    return old;
}

int open_new(const std::filesystem::path& path) {
    return ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC | O_NOFOLLOW,
                  0600);
}

bool read_lines(const std::filesystem::path& path, std::vector<std::string>& lines,
                std::string& error) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return true;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot read " + path.string() + ": " + std::strerror(errno);
        return false;
    }
    std::ostringstream text;
    text << in.rdbuf();
    const std::string all = text.str();
    std::size_t begin = 0;
    for (auto end = all.find('\n'); end != std::string::npos; end = all.find('\n', begin)) {
        lines.push_back(all.substr(begin, end - begin));
        begin = end + 1;
    }
    return true;
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
    : path_(std::move(path)), old_path_(old_path_of(path_)), fd_(fd) {
    std::error_code ec;
    old_exists_ = std::filesystem::exists(old_path_, ec);
    thread_ = std::thread([this] { run(); });
}

Journal::~Journal() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
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
    std::lock_guard lock(mutex_);
    return syncs_;
}

void Journal::push(Item item) {
    {
        std::lock_guard lock(mutex_);
        queue_.push_back(std::move(item));
    }
    wake_.notify_one();
}

void Journal::run() {
    std::vector<Item> batch;
    std::string buffer;
    std::vector<Durable> waiting;
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping, and everything is written
        batch.swap(queue_);
        lock.unlock();
        for (auto& item : batch) {
            switch (item.kind) {
                case Item::Kind::Record:
                    buffer += item.record;
                    buffer += '\n';
                    waiting.push_back(std::move(item.done));
                    break;
                case Item::Kind::Rotate:
                    flush(buffer, waiting);
                    do_rotate();
                    last_rotation_ = item.rotation;
                    break;
                case Item::Kind::DropOld:
                    if (item.rotation != last_rotation_) break;
                    flush(buffer, waiting);
                    ::unlink(old_path_.c_str());
                    old_exists_ = false;
                    break;
            }
        }
        batch.clear();
        flush(buffer, waiting);
        lock.lock();
    }
}

void Journal::flush(std::string& buffer, std::vector<Durable>& waiting) {
    if (waiting.empty()) return;
    const bool written = fd_ >= 0 && write_all(fd_, buffer) && ::fdatasync(fd_) == 0;
    {
        std::lock_guard lock(mutex_);
        ++syncs_;
    }
    for (auto& done : waiting) {
        if (done) done(written);
    }
    buffer.clear();
    waiting.clear();
}

void Journal::do_rotate() {
    if (old_exists_) {
        // The last save failed, so PATH.old still holds records no state file has: keep them,
        // with these after them.
        std::vector<std::string> lines;
        std::string error;
        read_lines(path_, lines, error);
        int old = ::open(old_path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
        std::string text;
        for (const auto& line : lines)
            text += line + "\n";
        if (old >= 0) {
            write_all(old, text);
            ::fdatasync(old);
            ::close(old);
        }
        if (fd_ >= 0) ::ftruncate(fd_, 0);
        return;
    }
    if (fd_ >= 0) ::close(fd_);
    ::rename(path_.c_str(), old_path_.c_str());
    fd_ = open_new(path_);
    sync_directory_of(path_);
    old_exists_ = true;
}

protocol::Result<std::vector<std::string>, std::string> read_journal(
    const std::filesystem::path& path) {
    std::vector<std::string> lines;
    std::string error;
    if (!read_lines(old_path_of(path), lines, error) || !read_lines(path, lines, error)) {
        return error;
    }
    return lines;
}

void remove_journal(const std::filesystem::path& path) {
    ::unlink(path.c_str());
    ::unlink(old_path_of(path).c_str());
    sync_directory_of(path);
}

}  // namespace mblab::server
