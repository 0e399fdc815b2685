#pragma once

#include <sys/resource.h>
#include <unistd.h>

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

// The thread behind the journal and the state saver, so that their writes and fsyncs never stall
// the server's thread. The owner keeps its queue under mutex() and calls wake() after adding to
// it. stop() returns only once the work handed over is done: what the server acknowledged is
// written before the owner goes.
namespace mblab::server {

class WorkThread {
  public:
    using Lock = std::unique_lock<std::mutex>;

    WorkThread() = default;
    ~WorkThread() { stop(); }
    WorkThread(const WorkThread&) = delete;
    WorkThread& operator=(const WorkThread&) = delete;

    // `pending()`, asked under the lock, says whether work waits. `turn(lock)` does some of it,
    // called with the lock held; it may unlock while it works and returns holding it again.
    // A positive `niceness` puts the thread below the server's: on a machine with few cores the
    // work would otherwise take the core the server needs, and stall clients after all.
    void start(std::function<bool()> pending, std::function<void(Lock&)> turn, int niceness = 0) {
        thread_ =
            std::thread([this, pending = std::move(pending), turn = std::move(turn), niceness] {
                if (niceness != 0)
                    ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), niceness);
                Lock lock(mutex_);
                for (;;) {
                    wake_.wait(lock, [&] { return stopping_ || pending(); });
                    if (!pending()) return;  // asked to stop, and everything is done
                    turn(lock);
                }
            });
    }

    std::mutex& mutex() const { return mutex_; }
    void wake() { wake_.notify_one(); }

    // Finishes the work handed over, then joins the thread; later calls do nothing.
    void stop() {
        if (!thread_.joinable()) return;
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_one();
        thread_.join();
    }

  private:
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace mblab::server
