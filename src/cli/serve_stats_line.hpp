#pragma once

#include <fmt/core.h>
#include <unistd.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "server/tcp_server.hpp"

namespace mblab::cli {

// The counters of every server, summed, on one line once a second: a live line on a terminal,
// a line per second in a log.
class StatsLine {
  public:
    explicit StatsLine(const std::vector<std::unique_ptr<server::TcpServer>>& servers)
        : servers_(servers), live_(::isatty(STDERR_FILENO) != 0) {}

    void print();
    void finish() const {
        if (live_) fmt::print(stderr, "\n");
    }

  private:
    const std::vector<std::unique_ptr<server::TcpServer>>& servers_;
    bool live_;
    std::uint64_t last_requests_ = 0;
    std::uint64_t last_exceptions_ = 0;
};

}  // namespace mblab::cli
