#pragma once

#include <CLI/CLI.hpp>
#include <functional>

// Each subcommand lives in its own file and registers itself on the top-level app. The returned
// callback runs the command and yields the process exit status.
namespace mblab::cli {

using CommandRunner = std::function<int()>;

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;  // a check failed / the device answered an exception
inline constexpr int kExitUsage = 2;   // bad arguments, bad files, unreachable target

void add_serve_command(CLI::App& app, CommandRunner& runner);
void add_conform_command(CLI::App& app, CommandRunner& runner);
void add_read_command(CLI::App& app, CommandRunner& runner);
void add_write_command(CLI::App& app, CommandRunner& runner);
void add_diag_command(CLI::App& app, CommandRunner& runner);
void add_devid_command(CLI::App& app, CommandRunner& runner);
void add_raw_command(CLI::App& app, CommandRunner& runner);
void add_watch_command(CLI::App& app, CommandRunner& runner);
void add_load_command(CLI::App& app, CommandRunner& runner);
void add_pki_command(CLI::App& app, CommandRunner& runner);

}  // namespace mblab::cli
