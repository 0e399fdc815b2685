#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "device/reference_device.hpp"
#include "server/background_server.hpp"

// What the `mblab load` tests share: reference devices on loopback, running the binary with its
// reports in temp files, and reading the reports.
namespace mblab::test {

std::string slurp(const std::string& path);

// The reference device with extra profile text (fault rules for its unit) on an ephemeral port.
struct Device {
    explicit Device(const std::string& extra = "");
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port); }

    std::unique_ptr<device::ReferenceDevice> device;  // outlives the server
    std::unique_ptr<server::BackgroundServer> server;
    std::uint16_t port = 0;
};

struct LoadRun {
    std::optional<int> status;
    std::string out;
    std::string err;
    nlohmann::json report;
    std::string junit;
};

// A temp file of the running test.
std::string temp(const std::string& name);

// `mblab load --json NAME.json --junit NAME.xml ARGS...`
std::vector<std::string> load_argv(const std::string& name, const std::vector<std::string>& args);

// Collects what a finished (or stopped) child wrote, and its reports.
LoadRun finish(ChildProcess& child, const std::string& name, std::string out = {});

LoadRun mblab_load(const std::string& name, const std::vector<std::string>& args);

// Requests of the given function code sent to a node, summed over its exchanges.
std::uint64_t sent_with_function(const nlohmann::json& node, int function);

std::uint64_t failures(const nlohmann::json& node, const char* kind);

// The node passed: answers to every request, no failure.
void expect_clean(const nlohmann::json& node);

}  // namespace mblab::test
