#include "transport/socket_poller.hpp"

#include <unistd.h>

#include <asio/error.hpp>
#include <asio/execution/context.hpp>
#include <asio/post.hpp>
#include <asio/query.hpp>
#include <cerrno>
#include <system_error>

namespace mblab::transport {

namespace {

constexpr std::size_t kBatch = 256;  // events taken per wake-up

asio::detail::reactor& reactor_of(const asio::any_io_executor& executor) {
    auto& reactor =
        asio::use_service<asio::detail::reactor>(asio::query(executor, asio::execution::context));
    reactor.init_task();  // the io_context waits in this reactor, as for any descriptor of its
    return reactor;
}

}  // namespace

// The set's wait in the reactor. It completes as soon as it is performed: when the set became
// ready, or at once while it is being started when the set became ready while nothing waited.
// "Exhausted" keeps the reactor from trying it early the next time.
class SocketPoller::WaitOperation final : public asio::detail::reactor_op {
  public:
    explicit WaitOperation(std::weak_ptr<SocketPoller> poller)
        : reactor_op(asio::error_code(), &perform, &complete), poller_(std::move(poller)) {}

  private:
    static status perform(reactor_op*) { return done_and_exhausted; }
    // `owner` is null when the io_context is destroyed with the operation pending.
    static void complete(void* owner, asio::detail::scheduler_operation* base,
                         const asio::error_code&, std::size_t) {
        std::unique_ptr<WaitOperation> operation(static_cast<WaitOperation*>(base));
        const auto poller = operation->poller_.lock();
        if (!owner || !poller) return;
        const auto ec = operation->ec_;
        // Kept for the next wait: no allocation per request.
        if (!ec) poller->spare_ = std::move(operation);
        poller->on_wait(ec);
    }

    std::weak_ptr<SocketPoller> poller_;
};

std::shared_ptr<SocketPoller> SocketPoller::create(asio::any_io_executor executor) {
    return std::shared_ptr<SocketPoller>(new SocketPoller(std::move(executor)));
}

SocketPoller::SocketPoller(asio::any_io_executor executor)
    : executor_(std::move(executor)), reactor_(reactor_of(executor_)), events_(kBatch) {
    if (!epoll_.ok()) throw std::system_error(errno, std::generic_category(), "epoll_create1");
    if (const int error = reactor_.register_descriptor(epoll_.fd(), registration_); error != 0)
        throw std::system_error(error, std::generic_category(), "epoll_ctl");
}

SocketPoller::~SocketPoller() {
    // A pending wait completes as aborted and finds the poller gone.
    reactor_.deregister_descriptor(epoll_.fd(), registration_, false);
    reactor_.cleanup_descriptor_data(registration_);
}

SocketPoller::Slot* SocketPoller::find(int fd) {
    if (fd < 0 || static_cast<std::size_t>(fd) >= slots_.size()) return nullptr;
    auto& slot = slots_[static_cast<std::size_t>(fd)];
    return slot.watcher ? &slot : nullptr;
}

namespace {

std::uint64_t key_of(int fd, std::uint32_t generation) {
    return (std::uint64_t{generation} << 32) | static_cast<std::uint32_t>(fd);
}

}  // namespace

bool SocketPoller::add(int fd, Watcher& watcher, std::uint32_t events) {
    if (fd < 0 || find(fd)) {
        errno = fd < 0 ? EBADF : EEXIST;
        return false;
    }
    const auto index = static_cast<std::size_t>(fd);
    if (index >= slots_.size()) slots_.resize(index + 1);
    auto& slot = slots_[index];
    // Events still queued for the descriptor's last watcher carry the old generation.
    const std::uint32_t generation = slot.generation + 1;
    if (!epoll_.add(fd, key_of(fd, generation), events)) return false;
    slot = {&watcher, events, generation};
    ++live_;
    wait();
    return true;
}

void SocketPoller::modify(int fd, std::uint32_t events) {
    auto* slot = find(fd);
    if (!slot || slot->events == events) return;
    if (!epoll_.modify(fd, key_of(fd, slot->generation), events)) return;
    const bool more = (events & ~slot->events) != 0;
    slot->events = events;
    // Input that came while the socket was not watched for it may wake nobody once it is: the
    // set's entry for it can still be queued from before, and a queued entry makes no new edge.
    if (more) look_again();
}

void SocketPoller::remove(int fd) {
    auto* slot = find(fd);
    if (!slot) return;
    epoll_.remove(fd);
    slot->watcher = nullptr;
    slot->events = 0;
    --live_;
    // Nothing left to watch: no pending wait may keep the io_context running.
    if (live_ == 0 && wait_pending_) reactor_.cancel_ops(epoll_.fd(), registration_);
}

void SocketPoller::wait() {
    if (wait_pending_ || look_pending_ || live_ == 0) return;
    wait_pending_ = true;
    auto operation = std::move(spare_);
    if (!operation) operation = std::make_unique<WaitOperation>(weak_from_this());
    reactor_.start_op(asio::detail::reactor::read_op, epoll_.fd(), registration_,
                      operation.release(), false, true);
}

void SocketPoller::on_wait(const asio::error_code& ec) {
    wait_pending_ = false;
    // After a cancel, a socket added since still needs the wait.
    if (!ec && dispatch()) {
        look_again();
    } else {
        wait();
    }
}

void SocketPoller::look_again() {
    if (look_pending_ || live_ == 0) return;
    // After the io_context's other work; a busy set would otherwise cost a wake-up each time.
    look_pending_ = true;
    asio::post(executor_, [weak = weak_from_this()] {
        const auto self = weak.lock();
        if (!self) return;
        self->look_pending_ = false;
        if (self->dispatch()) {
            self->look_again();
        } else {
            self->wait();
        }
    });
}

bool SocketPoller::dispatch() {
    const int count = epoll_.wait(events_, 0);
    bool again = count > 1 || count == static_cast<int>(events_.size());
    for (int i = 0; i < count; ++i) {
        const auto& event = events_[static_cast<std::size_t>(i)];
        const auto& slot = slots_[static_cast<std::uint32_t>(event.data.u64)];
        // Removed during this batch, and perhaps added again since: not for this watcher.
        if (!slot.watcher || slot.generation != static_cast<std::uint32_t>(event.data.u64 >> 32))
            continue;
        again = slot.watcher->on_ready(event.events) || again;
    }
    return again && live_ > 0;
}

}  // namespace mblab::transport
