#pragma once

#include <gtest/gtest.h>
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

// Runs a program (the real `mblab`) with its stdout and stderr on pipes. Every wait has a
// timeout; the destructor kills a child that is still running, by its own pid.
namespace mblab::test {

class ChildProcess {
  public:
    explicit ChildProcess(const std::vector<std::string>& argv);
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    bool started() const { return pid_ > 0; }
    pid_t pid() const { return pid_; }
    // One line of stdout without its newline; nullopt on timeout or end of output.
    std::optional<std::string> read_stdout_line(std::chrono::milliseconds timeout);
    void signal(int signal_number) const;
    // The exit status, or nullopt if it did not exit in time (or died of a signal).
    std::optional<int> wait_exit(std::chrono::milliseconds timeout);
    // Everything written to stderr; call after wait_exit.
    std::string drain_stderr();
    // The child's peak resident memory in kB (its ru_maxrss), once wait_exit saw it exit; 0
    // before.
    long peak_rss_kb() const { return peak_rss_kb_; }

  private:
    pid_t pid_ = -1;
    int stdout_fd_ = -1;
    int stderr_fd_ = -1;
    std::string stdout_buffer_;
    bool exited_ = false;
    long peak_rss_kb_ = 0;
};

// What a program that ran to its end printed, and how it exited.
struct Ran {
    int status = -1;  // -1: did not exit in time
    std::string out;
    std::string err;
};

// Runs `argv` to its end and collects its output; each wait is at most `timeout`.
Ran run_program(const std::vector<std::string>& argv,
                std::chrono::seconds timeout = std::chrono::seconds(30));

// A run (Ran, or any result with `status` and `err`) that exited with `status` and printed
// exactly `err` on stderr.
template <class Run>
void expect_failed(const Run& ran, int status, const std::string& err) {
    EXPECT_EQ(ran.status, status) << ran.err;
    EXPECT_EQ(ran.err, err);
}

// SIGKILL to every process of ours whose command line holds `text` (a test's own temporary
// path): devices a test started through a shell, whose pids it cannot be sure of.
void kill_processes_naming(const std::string& text);

}  // namespace mblab::test
