#include "server/state_saver.hpp"

#include <algorithm>

#include "server/state_file.hpp"

namespace mblab::server {

namespace {

constexpr int kNiceness = 10;

}  // namespace

StateSaver::StateSaver(Write write) : write_(std::move(write)) {
    if (!write_) write_ = write_file_atomically;
    worker_.start([this] { return !queue_.empty(); },
                  [this](WorkThread::Lock& lock) { save_next(lock); }, kNiceness);
}

StateSaver::~StateSaver() {
    worker_.stop();
}

void StateSaver::save(std::filesystem::path path, device::StateSnapshot snapshot, Done done) {
    {
        std::lock_guard lock(worker_.mutex());
        auto waiting = std::find_if(queue_.begin(), queue_.end(),
                                    [&](const Job& job) { return job.path == path; });
        if (waiting != queue_.end()) {
            waiting->snapshot = std::move(snapshot);
            waiting->done = std::move(done);
        } else {
            queue_.push_back({std::move(path), std::move(snapshot), std::move(done)});
        }
    }
    worker_.wake();
}

void StateSaver::wait_idle() {
    WorkThread::Lock lock(worker_.mutex());
    idle_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void StateSaver::save_next(WorkThread::Lock& lock) {
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

}  // namespace mblab::server
