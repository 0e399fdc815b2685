#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/fuzz_monitor.hpp"
#include "cli/fuzz_output.hpp"
#include "security/tls_context.hpp"

// `mblab fuzz`'s options: what they hold and how they are registered (docs/robustness.md).
namespace mblab::cli {

struct FuzzCommandOptions {
    std::string target;
    std::uint64_t seed = 1;
    std::size_t cases = 1000;
    double duration = 0;  // seconds; 0: the case budget alone
    double rate = 200;
    std::size_t check_every = 1;
    int timeout_ms = 1000;
    int unit = 1;
    bool unit_given = false;
    std::string dut_file;
    std::string learn;
    std::string writable;
    bool allow_writes = false;
    std::string restart;
    std::string replay;
    std::string report_dir;
    bool keep_going = false;
    std::vector<std::string> classes;
    std::vector<std::string> skip_classes;
    MonitorChoice monitor;
    FuzzFiles files;  // an empty reproducer: finding-N.hex in the report directory
    int device_pid = 0;
    security::TlsFiles tls;  // the tester's certificate on mbaps://
    const Invocation* invocation = nullptr;
};

// Registers every option of `mblab fuzz` on `cmd`, into `options`.
void add_fuzz_options(CLI::App& cmd, FuzzCommandOptions& options);

}  // namespace mblab::cli
