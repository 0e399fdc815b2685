#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "client/raw_link.hpp"
#include "conformance/dut.hpp"

namespace mblab::conformance {

struct EngineOptions {
    std::chrono::milliseconds timeout{1000};  // for each answer
    std::chrono::milliseconds connect_timeout{3000};
    std::size_t pipeline_depth = 16;  // requests in flight during sweeps and scans
};

// Told how far a long procedure has come; the console shows it on a TTY.
class Progress {
  public:
    virtual ~Progress() = default;
    virtual void update(std::string_view what, std::size_t done, std::size_t total) = 0;
    virtual void clear() = 0;
};

// The connection to the device under test, shared by every case of a run. It reconnects when a
// case left it closed or out of step, and counts the requests sent.
class Session {
  public:
    Session(client::Endpoint endpoint, Dut dut, EngineOptions options,
            client::LinkObserver* observer = nullptr, Progress* progress = nullptr);

    const client::Endpoint& endpoint() const { return endpoint_; }
    const Dut& dut() const { return dut_; }
    const DutFacts& facts() const { return facts_; }
    const EngineOptions& options() const { return options_; }
    Progress* progress() const { return progress_; }

    // The open connection, connecting first when needed; nullptr with `error` set when the device
    // cannot be reached.
    client::RawLink* link(client::LinkError& error);
    // Closes the connection so the next case starts on a fresh one.
    void close();

    // Sends `count` requests held in `bytes`, written as pieces cut at `split` with `delay`
    // between them (so they leave as separate TCP segments).
    bool send(std::span<const std::uint8_t> bytes, std::size_t count, client::LinkError& error,
              std::span<const std::size_t> split = {},
              std::chrono::milliseconds delay = std::chrono::milliseconds(0));
    client::Received receive_frame(std::chrono::milliseconds timeout);
    client::Received receive_any(std::chrono::milliseconds timeout);

    std::size_t requests() const { return requests_; }

  private:
    client::Endpoint endpoint_;
    Dut dut_;
    DutFacts facts_;
    EngineOptions options_;
    client::LinkObserver* observer_;
    Progress* progress_;
    std::optional<client::RawLink> link_;
    std::size_t requests_ = 0;
};

}  // namespace mblab::conformance
