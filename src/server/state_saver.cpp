#include "server/state_saver.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

#include "server/state_file.hpp"

namespace mblab::server {

namespace {

constexpr int kNiceness = 10;

}  // namespace

StateSaver::StateSaver(Write write) : write_(std::move(write)) {
    if (!write_) write_ = write_file_atomically;
    thread_ = std::thread([this] { run(); });
}

StateSaver::~StateSaver() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

void StateSaver::save(std::filesystem::path path, device::StateSnapshot snapshot, Done done) {
    {
        std::lock_guard lock(mutex_);
        auto waiting = std::find_if(queue_.begin(), queue_.end(),
                                    [&](const Job& job) { return job.path == path; });
        if (waiting != queue_.end()) {
            waiting->snapshot = std::move(snapshot);
            waiting->done = std::move(done);
        } else {
            queue_.push_back({std::move(path), std::move(snapshot), std::move(done)});
        }
    }
    wake_.notify_one();
}

void StateSaver::wait_idle() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void StateSaver::run() {
    // Below the server's thread: on a machine with few cores, the text of a large state would
    // otherwise take the core the server needs, and the save would stall clients after all.
    ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), kNiceness);
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;
        Job job = std::move(queue_.front());
        queue_.pop_front();
        busy_ = true;
        lock.unlock();
        std::string error;
        const bool saved = write_(job.path, job.snapshot.to_json(), error);
        if (job.done) job.done(saved, error);
        lock.lock();
        busy_ = false;
        if (queue_.empty()) idle_.notify_all();
    }
}

}  // namespace mblab::server
