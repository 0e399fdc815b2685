#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "cli/commands.hpp"

int main(int argc, char** argv) {
    using namespace mblab::cli;
    CLI::App app{"mblab: a Modbus conformance lab (tester, reference device, load test, client)",
                 "mblab"};
    app.set_version_flag("--version", std::string("mblab ") + MBLAB_VERSION);
    app.require_subcommand(1);
    CommandRunner runner;
    add_conform_command(app, runner);
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
        fmt::print(stderr, "mblab: {}\n", e.what());
        fmt::print(stderr, "run 'mblab --help' for usage\n");
        return kExitUsage;
    }
    try {
        return runner ? runner() : kExitUsage;
    } catch (const std::exception& e) {
        fmt::print(stderr, "mblab: {}\n", e.what());
        return kExitUsage;
    }
}
