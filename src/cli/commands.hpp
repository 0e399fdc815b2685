#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// Each subcommand lives in its own file and registers itself on the top-level app. The returned
// callback runs the command and yields the process exit status.
namespace mblab::cli {

using CommandRunner = std::function<int()>;

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;  // a check failed / the device answered an exception
inline constexpr int kExitUsage = 2;   // bad arguments, bad files, unreachable target

// A help text written as it prints, in a raw string literal that opens on a line of its own:
// drops that first line break.
inline std::string help_text(std::string_view raw) {
    if (!raw.empty() && raw.front() == '\n') raw.remove_prefix(1);
    return std::string(raw);
}

// Registers command NAME under `parent`; `run` is called with its options when the command line
// chose it. The command's arguments are added to the returned subcommand.
template <class Options>
std::pair<CLI::App*, std::shared_ptr<Options>> add_command(CLI::App& parent, CommandRunner& runner,
                                                           const std::string& name,
                                                           const std::string& description,
                                                           const std::string& footer,
                                                           int (*run)(const Options&)) {
    auto options = std::make_shared<Options>();
    CLI::App* command = parent.add_subcommand(name, description);
    if (!footer.empty()) command->footer(footer);
    command->callback(
        [options, run, &runner] { runner = [options, run] { return run(*options); }; });
    return {command, options};
}

// How this process was started and what it is, for reports that must say so later. Filled in by
// main, which alone sees argv whole and includes the generated build_info.hpp (so a new commit
// rebuilds main.cpp only).
struct Invocation {
    std::string version;
    std::string commit;
    std::vector<std::string> argv;
};

void add_serve_command(CLI::App& app, CommandRunner& runner);
// `invocation` must outlive the runner.
void add_conform_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation);
// `invocation` must outlive the runner.
void add_conform_client_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation);
void add_read_command(CLI::App& app, CommandRunner& runner);
void add_sunspec_command(CLI::App& app, CommandRunner& runner);
void add_write_command(CLI::App& app, CommandRunner& runner);
void add_diag_command(CLI::App& app, CommandRunner& runner);
void add_devid_command(CLI::App& app, CommandRunner& runner);
void add_raw_command(CLI::App& app, CommandRunner& runner);
void add_watch_command(CLI::App& app, CommandRunner& runner);
void add_load_command(CLI::App& app, CommandRunner& runner);
void add_pki_command(CLI::App& app, CommandRunner& runner);
// `invocation` must outlive the runner.
void add_fuzz_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation);
void add_profile_command(CLI::App& app, CommandRunner& runner);
// `invocation` must outlive the runner.
void add_scan_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation);

}  // namespace mblab::cli
