#include "transport/socket_poller.hpp"

#include <unistd.h>

#include <asio/error.hpp>
#include <asio/post.hpp>
#include <cerrno>
#include <system_error>

namespace mblab::transport {

namespace {

constexpr std::size_t kBatch = 256;  // events taken per wake-up

// The set's descriptor for the io_context to watch and, in the end, to close: closing it also
// takes it out of the io_context's own epoll set, where a separate close would cost an
// epoll_ctl first.
int watched_descriptor(EpollSet& epoll) {
    if (!epoll.ok()) throw std::system_error(errno, std::generic_category(), "epoll_create1");
    return epoll.hand_over();
}

}  // namespace

std::shared_ptr<SocketPoller> SocketPoller::create(asio::any_io_executor executor) {
    return std::shared_ptr<SocketPoller>(new SocketPoller(std::move(executor)));
}

SocketPoller::SocketPoller(asio::any_io_executor executor)
    : descriptor_(std::move(executor), watched_descriptor(epoll_)), events_(kBatch) {}

SocketPoller::~SocketPoller() = default;  // the descriptor closes the epoll set

SocketPoller::Entry* SocketPoller::only_entry() const {
    if (live_ != 1) return nullptr;
    for (const auto& entry : entries_) {
        if (entry) return entry.get();
    }
    return nullptr;
}

SocketPoller::Entry* SocketPoller::find(int fd) const {
    if (fd < 0 || static_cast<std::size_t>(fd) >= entries_.size()) return nullptr;
    return entries_[static_cast<std::size_t>(fd)].get();
}

bool SocketPoller::add(int fd, const std::shared_ptr<Watcher>& watcher, std::uint32_t events) {
    if (fd < 0 || find(fd)) {
        errno = fd < 0 ? EBADF : EEXIST;
        return false;
    }
    auto entry = std::make_unique<Entry>();
    entry->events = events;
    entry->watcher = watcher;
    if (!epoll_.add(fd, entry.get(), events)) return false;
    auto index = static_cast<std::size_t>(fd);
    if (index >= entries_.size()) entries_.resize(index + 1);
    entries_[index] = std::move(entry);
    ++live_;
    sole_ = only_entry();
    wait();
    return true;
}

void SocketPoller::modify(int fd, std::uint32_t events) {
    auto* entry = find(fd);
    if (!entry || entry->events == events) return;
    if (epoll_.modify(fd, entry, events)) entry->events = events;
}

void SocketPoller::remove(int fd) {
    auto* entry = find(fd);
    if (!entry) return;
    epoll_.remove(fd);
    entry->removed = true;
    auto& slot = entries_[static_cast<std::size_t>(fd)];
    // An event of the batch being delivered may still point at the entry.
    if (dispatching_) removed_.push_back(std::move(slot));
    slot.reset();
    --live_;
    sole_ = only_entry();
    // Nothing left to watch: no pending wait may keep the io_context running.
    if (live_ == 0 && waiting_) {
        asio::error_code ignored;
        descriptor_.cancel(ignored);
    }
}

void SocketPoller::wait() {
    if (waiting_ || live_ == 0) return;
    waiting_ = true;
    descriptor_.async_wait(asio::posix::stream_descriptor::wait_read,
                           [weak = weak_from_this()](const asio::error_code& ec) {
                               if (auto self = weak.lock()) self->on_wait(ec);
                           });
}

void SocketPoller::on_wait(const asio::error_code& ec) {
    waiting_ = false;
    if (!ec && dispatch() > 1) {
        // Busy: look again after the io_context's other work instead of waiting for a wake-up,
        // which would cost re-arming the descriptor (epoll_ctl) and a second epoll_wait.
        waiting_ = true;
        asio::post(descriptor_.get_executor(), [weak = weak_from_this()] {
            if (auto self = weak.lock()) self->on_wait({});
        });
        return;
    }
    // After a cancel, a socket added since still needs the wait.
    if (ec != asio::error::bad_descriptor) wait();
}

int SocketPoller::dispatch() {
    int count = 0;
    if (sole_ && sole_->events == EPOLLIN) {
        events_[0].events = EPOLLIN;
        events_[0].data.ptr = sole_;
        count = 1;
    } else {
        count = epoll_.wait(events_, 0);
    }
    dispatching_ = true;
    for (int i = 0; i < count; ++i) {
        const auto& event = events_[static_cast<std::size_t>(i)];
        auto* entry = static_cast<Entry*>(event.data.ptr);
        if (entry->removed) continue;
        if (auto watcher = entry->watcher.lock()) watcher->on_ready(event.events);
    }
    dispatching_ = false;
    removed_.clear();
    return count;
}

}  // namespace mblab::transport
