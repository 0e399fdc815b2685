#pragma once

// The real `mblab serve` process for the integration tests: started on ephemeral ports (read back
// from the line it prints), and refusals at start (exit 2, one line on stderr).
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "blocking_client.hpp"
#include "child_process.hpp"

namespace mblab::test {

inline std::vector<std::string> serve_args(std::vector<std::string> extra) {
    std::vector<std::string> args{MBLAB_BINARY, "serve"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

// Starts `mblab serve` on ephemeral ports and reads the ports from its first line.
class Serve {
  public:
    explicit Serve(std::vector<std::string> extra) : child_(serve_args(std::move(extra))) {
        if (auto line = child_.read_stdout_line(std::chrono::seconds(10))) {
            line_ = *line;
            std::regex url("tcp://127\\.0\\.0\\.1:([0-9]+)");
            for (std::sregex_iterator it(line_.begin(), line_.end(), url), end; it != end; ++it) {
                ports_.push_back(static_cast<std::uint16_t>(std::stoi((*it)[1])));
            }
        }
    }
    ChildProcess& process() { return child_; }
    const std::string& line() const { return line_; }
    const std::vector<std::uint16_t>& ports() const { return ports_; }
    BlockingClient connect(std::size_t device = 0) const {
        return device < ports_.size() ? BlockingClient(ports_[device]) : BlockingClient();
    }
    // SIGTERM, then the exit status (nullopt: it did not exit cleanly in time).
    std::optional<int> terminate() {
        child_.signal(SIGTERM);
        return child_.wait_exit(std::chrono::seconds(10));
    }

  private:
    ChildProcess child_;
    std::string line_;
    std::vector<std::uint16_t> ports_;
};

struct Failure {
    std::optional<int> status;
    std::string err;
};

inline Failure run_failing(std::vector<std::string> extra) {
    ChildProcess child(serve_args(std::move(extra)));
    Failure out;
    out.status = child.wait_exit(std::chrono::seconds(10));
    out.err = child.drain_stderr();
    return out;
}

// A refusal: exit 2 and one line on stderr that starts with `start`.
inline void expect_one_line(const Failure& failure, const std::string& start) {
    EXPECT_EQ(failure.status, 2);
    EXPECT_EQ(std::count(failure.err.begin(), failure.err.end(), '\n'), 1);
    EXPECT_TRUE(failure.err.starts_with(start)) << failure.err;
}

}  // namespace mblab::test
