#pragma once

#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include "device/reference_device.hpp"

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
    void run();

    Write write_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable idle_;
    std::deque<Job> queue_;
    bool busy_ = false;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace mblab::server
