#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "server/traffic_log.hpp"

// `mblab serve --log [FILE]`: each request and its answer as a line on standard error or in
// FILE, rotated by size (server/traffic_log.hpp).
namespace mblab::cli {

struct LogOptions {
    std::string file;                     // "" or "-": standard error
    const CLI::Option* option = nullptr;  // --log, given or not: a bare --log sets no value
    std::string format = "text";
    std::string max_size = "10M";
};

void add_log_options(CLI::App& command, LogOptions& options);

// The log `options` ask for, kept in a ring for the dashboard when `for_http`; nullptr when
// neither wants one, and with `error` set when FILE cannot be opened.
std::unique_ptr<server::TrafficLog> open_traffic_log(const LogOptions& options, bool for_http,
                                                     std::string& error);

}  // namespace mblab::cli
