#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "cli/build_info.hpp"
#include "cli/client_options.hpp"
#include "cli/commands.hpp"

namespace {

// The usage error on one line, naming the subcommand the user typed (or the unknown word in its
// place) and where help is.
std::string usage_line(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
    std::string names;
    for (const auto* sub : app.get_subcommands({}))
        names += (names.empty() ? "" : ", ") + sub->get_name();
    std::string command;
    std::string unknown;
    for (int i = 1; i < argc && command.empty() && unknown.empty(); ++i) {
        const std::string word = argv[i];
        if (word.empty() || word.front() == '-') continue;
        const auto subs =
            app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == word; });
        (subs.empty() ? unknown : command) = word;
    }
    if (command.empty() && !unknown.empty()) {
        return fmt::format("mblab: unknown command '{}' (commands: {})", unknown, names);
    }
    if (command.empty()) {
        return fmt::format("mblab: a command is required: {} (run 'mblab --help' for usage)",
                           names);
    }
    const std::string prefix = command.empty() ? "mblab" : "mblab " + command;
    return fmt::format("{}: {} (run '{} --help' for usage)", prefix, error.what(), prefix);
}

// conform's millisecond options take units as every other duration option does. conform
// declares them in its own file; they are reached here by name so that file need not change,
// and an option renamed there is skipped rather than stopping every command at startup.
void accept_conform_duration_units(CLI::App& app) {
    for (auto* command :
         app.get_subcommands([](const CLI::App* sub) { return sub->get_name() == "conform"; })) {
        for (const char* name : {"--timeout", "--settle"}) {
            if (auto* option = command->get_option_no_throw(name)) {
                mblab::cli::accept_duration_units(option, mblab::cli::DurationUnit::milliseconds,
                                                  true);
            }
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    using namespace mblab::cli;
    CLI::App app{"mblab: a Modbus conformance lab (tester, reference device, load test, client)",
                 "mblab"};
    app.set_version_flag("-V,--version", fmt::format("mblab {} (commit {})", kVersion, kCommit));
    app.require_subcommand(1);
    CommandRunner runner;
    add_conform_command(app, runner);
    accept_conform_duration_units(app);
    add_serve_command(app, runner);
    add_read_command(app, runner);
    add_write_command(app, runner);
    add_diag_command(app, runner);
    add_devid_command(app, runner);
    add_raw_command(app, runner);
    add_watch_command(app, runner);
    add_load_command(app, runner);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "{}\n", usage_line(app, e, argc, argv));
        return kExitUsage;
    }
    try {
        return runner ? runner() : kExitUsage;
    } catch (const std::exception& e) {
        fmt::print(stderr, "mblab: {}\n", e.what());
        return kExitUsage;
    }
}
