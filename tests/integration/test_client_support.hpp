#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "server_fixture.hpp"

// Shared by the test_client_*.cpp files: runs the real binary and names targets.
namespace mblab::test {

// Runs `mblab ARGS...` to its end (at most 30 s) and collects its output.
inline Ran run_mblab(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {MBLAB_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_program(argv);
}

// A usage error: `mblab ARGS...` exits 2 before doing anything, with `message` its only output.
inline void expect_usage(const std::vector<std::string>& args, const std::string& message) {
    const auto ran = run_mblab(args);
    EXPECT_EQ(ran.out, "");
    expect_failed(ran, 2, message);
}

inline std::string tcp_target(std::uint16_t port) {
    return "tcp://127.0.0.1:" + std::to_string(port);
}

// A client test against an in-process device: `mblab(...)` runs the binary with the target first.
class ClientCliTest : public ServerFixture {
  protected:
    Ran mblab(const std::string& command, std::vector<std::string> args) const {
        args.insert(args.begin(), {command, tcp_target(port_)});
        return run_mblab(args);
    }
    std::string target() const { return tcp_target(port_); }
};

// The same against the shipped reference profile.
class ReferenceCliTest : public ClientCliTest {
  protected:
    void SetUp() override { start_reference_server(); }
};

}  // namespace mblab::test
