#pragma once

// A fragile device (tests/devices/fragile_device.cpp) on a free loopback port, started and
// restarted by a shell command, for the tests of `mblab fuzz`.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "support/ports.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {

inline bool accepts(std::uint16_t port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
    ::close(fd);
    return ok;
}

// The reproducer's step lines (comments dropped).
inline std::vector<std::string> steps_of(const std::string& text) {
    std::vector<std::string> steps;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (!line.empty() && line[0] != '#') steps.push_back(line);
    }
    return steps;
}

// A fragile device on a free loopback port, started (and restarted) by a shell command.
class FuzzFragile : public ::testing::Test {
  protected:
    void start(const std::string& mode) {
        port_ = closed_port();
        const auto pid_file = (dir_ / "device.pid").string();
        restart_ = "kill $(cat " + pid_file + " 2>/dev/null) 2>/dev/null; " +
                   std::string(MBLAB_FRAGILE_DEVICE) + " " + mode + " " + std::to_string(port_) +
                   " " + pid_file + " >/dev/null 2>&1 </dev/null &";
        restart();
    }
    // Runs the restart command and waits until the new device (a new pid) listens.
    void restart() {
        const auto before = file_text(dir_ / "device.pid");
        ASSERT_EQ(std::system(restart_.c_str()), 0);
        for (int i = 0; i < 250 && (file_text(dir_ / "device.pid") == before || !accepts(port_));
             ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ASSERT_TRUE(accepts(port_));
    }
    // Every device this test started: the one fuzz left running after minimising may not have
    // written its pid yet.
    void TearDown() override { kill_processes_naming((dir_ / "device.pid").string()); }
    Ran fuzz(std::vector<std::string> args) const {
        args.insert(args.begin(), {"fuzz", tcp_target(port_), "--reproducer",
                                   (dir_ / "finding.hex").string(), "--rate", "0"});
        return run_mblab(args);
    }
    // Fuzzes the started device with `args`: the run must exit `status` and its report say
    // `words`. Returns the run for the test's further checks.
    Ran expect_fuzz(std::vector<std::string> args, int status, const std::string& words) const {
        auto ran = fuzz(std::move(args));
        EXPECT_EQ(ran.status, status) << ran.out << ran.err;
        EXPECT_NE(ran.out.find(words), std::string::npos) << ran.out;
        return ran;
    }
    std::vector<std::string> reproducer() const {
        return steps_of(file_text(dir_ / "finding.hex"));
    }

    TempDir dir_;
    std::uint16_t port_ = 0;
    std::string restart_;
};

}  // namespace mblab::test
