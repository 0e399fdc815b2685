#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/build_info.hpp"
#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/help_format.hpp"
#include "cli/number_text.hpp"
#include "support/json_document.hpp"
#include "support/suggestion.hpp"

namespace {

// For an unexpected word in a command's arguments that looks like an option: the option it
// probably was. Only long options are matched; a one-letter one is too short to guess from.
std::optional<std::string> option_suggestion(const CLI::App& command, int first, int argc,
                                             char** argv) {
    std::vector<std::string> names;
    for (const auto* option : command.get_options()) {
        for (const auto& name : option->get_lnames())
            names.push_back("--" + name);
    }
    for (int i = first; i < argc; ++i) {
        std::string word = argv[i];
        if (word == "--") break;
        if (!word.starts_with("--")) continue;
        word = word.substr(0, word.find('='));
        if (std::find(names.begin(), names.end(), word) != names.end()) continue;
        if (auto near = mblab::support::nearest(word, names))
            return fmt::format("{}; did you mean {}?", word, *near);
        return std::nullopt;
    }
    return std::nullopt;
}

// A word CLI11 took for an option that is a negative number (-inf, -.5, -1e3 is taken as a value
// already): it needed -- before it.
std::optional<std::string> negative_value(int first, int argc, char** argv) {
    for (int i = first; i < argc; ++i) {
        const std::string_view word = argv[i];
        if (word == "--") break;
        if (word.size() > 1 && word[0] == '-' && word[1] != '-' && mblab::cli::parse_real(word)) {
            return std::string(word);
        }
    }
    return std::nullopt;
}

// The subcommand named on the command line (the first word that is not an option), and where.
std::pair<std::string, int> command_word(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word.empty() || word.front() == '-') continue;
        return {word, i};
    }
    return {"", 0};
}

// The client commands promise one JSON document on stdout with --json, a usage error included;
// CLI11 refuses a command line before the command runs, so main keeps that promise for them.
bool wants_json(const std::string& command, int first, int argc, char** argv) {
    static const std::vector<std::string> client_commands = {"read",  "write", "diag",
                                                             "devid", "raw",   "watch"};
    if (std::find(client_commands.begin(), client_commands.end(), command) ==
        client_commands.end()) {
        return false;
    }
    for (int i = first; i < argc; ++i) {
        const std::string_view word = argv[i];
        if (word == "--") break;
        if (word == "--json") return true;
    }
    return false;
}

// CLI11 2.1 honours -- in a subcommand only while one of its positionals still lacks a value
// (App::_has_remaining_positionals), so `write T register 7 -- -.5` had -.5 refused as an
// unknown option. The words after -- are kept from CLI11 and given to the command's last
// positional (ARGS, HEX, DATA) once the rest is parsed; when the rest does not parse alone (a
// required positional comes after --), CLI11 gets the whole line, and handles -- itself.
void parse_command_line(CLI::App& app, int argc, char** argv) {
    const auto [command, index] = command_word(argc, argv);
    int end = argc;
    for (int i = index + 1; index > 0 && i < argc; ++i) {
        if (std::string_view(argv[i]) == "--") {
            end = i;
            break;
        }
    }
    if (end == argc) {
        app.parse(argc, argv);
        return;
    }
    try {
        app.parse(end, argv);
    } catch (const CLI::ParseError&) {
        app.parse(argc, argv);
        return;
    }
    const auto parsed = app.get_subcommands();
    const auto positionals =
        parsed.empty()
            ? std::vector<CLI::Option*>{}
            : parsed.front()->get_options([](CLI::Option* o) { return o->get_positional(); });
    if (positionals.empty()) {
        // Nothing takes them: CLI11's own refusal of the whole line.
        app.parse(argc, argv);
        return;
    }
    CLI::Option* last = positionals.back();
    for (int i = end + 1; i < argc; ++i)
        last->add_result(argv[i]);
    last->run_callback();
}

// The usage error on one line, naming the subcommand the user typed (or the unknown word in its
// place) and where help is; a mistyped command or option gets the nearest one suggested.
std::string usage_line(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
    std::string names;
    std::vector<std::string> commands;
    for (const auto* sub : app.get_subcommands({})) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        commands.push_back(sub->get_name());
    }
    std::string command;
    std::string unknown;
    int command_index = 0;
    for (int i = 1; i < argc && command.empty() && unknown.empty(); ++i) {
        const std::string word = argv[i];
        if (word.empty() || word.front() == '-') continue;
        const auto subs =
            app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == word; });
        (subs.empty() ? unknown : command) = word;
        command_index = i;
    }
    if (command.empty() && !unknown.empty()) {
        if (auto near = mblab::support::nearest(unknown, commands)) {
            return fmt::format("mblab: unknown command '{}'; did you mean '{}'?", unknown, *near);
        }
        return fmt::format("mblab: unknown command '{}' (commands: {})", unknown, names);
    }
    if (command.empty()) {
        return fmt::format("mblab: a command is required: {} (run 'mblab --help' for usage)",
                           names);
    }
    const std::string prefix = "mblab " + command;
    if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) {
        if (auto suggestion =
                option_suggestion(*app.get_subcommand(command), command_index + 1, argc, argv)) {
            return fmt::format("{}: unknown option {} (run '{} --help' for usage)", prefix,
                               *suggestion, prefix);
        }
        if (auto negative = negative_value(command_index + 1, argc, argv)) {
            return fmt::format(
                "{}: {} was taken for an option: put -- before negative values, after the "
                "options (... -- {}) (run '{} --help' for usage)",
                prefix, *negative, *negative, prefix);
        }
    }
    return fmt::format("{}: {} (run '{} --help' for usage)", prefix, error.what(), prefix);
}

// conform's millisecond options take units as every other duration option does. conform
// declares them in its own file; they are reached here by name so that file need not change,
// and an option renamed there is skipped rather than stopping every command at startup.
void accept_conform_duration_units(CLI::App& app) {
    for (auto* command :
         app.get_subcommands([](const CLI::App* sub) { return sub->get_name() == "conform"; })) {
        // Every command's help ends with an example; conform's description has its exit statuses.
        if (command->get_footer().empty())
            command->footer("Example: mblab conform tcp://192.168.1.10:502 --json report.json");
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
    // Set before the commands are added: each takes its parent's formatter.
    app.formatter(std::make_shared<HelpFormatter>());
    CommandRunner runner;
    const Invocation invocation{kVersion, kCommit, std::vector<std::string>(argv, argv + argc)};
    add_conform_command(app, runner, invocation);
    add_conform_client_command(app, runner, invocation);
    accept_conform_duration_units(app);
    add_serve_command(app, runner);
    add_read_command(app, runner);
    add_write_command(app, runner);
    add_diag_command(app, runner);
    add_devid_command(app, runner);
    add_raw_command(app, runner);
    add_watch_command(app, runner);
    add_load_command(app, runner);
    add_pki_command(app, runner);
    add_fuzz_command(app, runner, invocation);
    add_profile_command(app, runner);
    add_scan_command(app, runner, invocation);
    add_sunspec_command(app, runner);
    app.footer(
        "Run 'mblab help COMMAND' (or 'mblab COMMAND --help') for a command's options, an example "
        "and its exit statuses.");
    // `mblab help [COMMAND]` is `mblab [COMMAND] --help`, so both print the same text. An unknown
    // COMMAND is left in place so it gets the unknown-command line, with its suggestion.
    std::vector<char*> args(argv, argv + argc);
    static char help_flag[] = "--help";
    if (args.size() >= 2 && std::string_view(args[1]) == "help") {
        args.erase(args.begin() + 1);
        if (args.size() > 2) args.resize(2);
        const bool known = args.size() == 1 || !app.get_subcommands([&](const CLI::App* sub) {
                                                       return sub->get_name() == args[1];
                                                   })
                                                    .empty();
        if (known) args.push_back(help_flag);
        argc = static_cast<int>(args.size());
        argv = args.data();
    }
    try {
        parse_command_line(app, argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        const std::string line = usage_line(app, e, argc, argv);
        fmt::print(stderr, "{}\n", line);
        const auto [command, index] = command_word(argc, argv);
        if (wants_json(command, index + 1, argc, argv)) {
            // The document a usage error of the running command prints, less what the command
            // line did not get as far as giving (target, unit).
            const std::string message = line.substr(line.find(": ") + 2);
            const nlohmann::json document = {{"command", command},
                                             {"ok", false},
                                             {"status", kExitUsage},
                                             {"error", {{"kind", "usage"}, {"message", message}}}};
            fmt::print("{}\n", mblab::json_document(document));
        }
        return kExitUsage;
    }
    try {
        return runner ? runner() : kExitUsage;
    } catch (const std::exception& e) {
        fmt::print(stderr, "mblab: {}\n", e.what());
        return kExitUsage;
    }
}
