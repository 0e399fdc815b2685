#pragma once

#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "device/reference_device.hpp"
#include "server/work_thread.hpp"

// Writes state files on a thread of its own, so that a save never stalls the server's thread:
// the server takes a snapshot (a copy under the device's lock) and hands it over; the JSON text,
// the write and the fsyncs happen here. Saves run one at a time in the order given; a snapshot
// for a file that still waits its turn replaces the older one, which it supersedes (that one's
// `done` is dropped), so slow saves never pile up.
namespace mblab::server {

class StateSaver {
  public:
    using Write = std::function<bool(const std::filesystem::path& path, std::string_view text,
                                     std::string& error)>;
    // How the save went; called on the saver's thread.
    using Done = std::function<void(bool saved, const std::string& error)>;

    // `write` replaces the file (write_file_atomically unless a test gives another).
    explicit StateSaver(Write write = {});
    // Finishes the saves handed over, then stops.
    ~StateSaver();
    StateSaver(const StateSaver&) = delete;
    StateSaver& operator=(const StateSaver&) = delete;

    void save(std::filesystem::path path, device::StateSnapshot snapshot, Done done);
    // Returns once every save handed over is done.
    void wait_idle();

  private:
    struct Job {
        std::filesystem::path path;
        device::StateSnapshot snapshot;
        Done done;
    };
    // One save, on the worker's thread; `lock` is held on entry and on return.
    void save_next(WorkThread::Lock& lock);

    Write write_;
    std::condition_variable idle_;
    std::deque<Job> queue_;  // under worker_.mutex(), as busy_
    bool busy_ = false;
    WorkThread worker_;  // last: it stops before what it works on goes
};

}  // namespace mblab::server
