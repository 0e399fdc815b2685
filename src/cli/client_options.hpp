#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>

#include "cli/commands.hpp"
#include "cli/value_format.hpp"
#include "client/client.hpp"
#include "client/client_error.hpp"
#include "security/tls_context.hpp"

// What the client commands (read, write, diag, devid, raw, watch) share: TARGET and the
// connection flags, the typed-value flags, and how a command reports its result and its errors.
namespace mblab::cli {

struct ClientOptions {
    std::string target;
    int unit = 1;
    int timeout_ms = 1000;
    int retries = 0;
    std::string decode;
    bool json = false;
    bool probe_units = true;  // off for watch: its polls stay the only requests on the wire
    bool no_probe = false;    // --no-probe
    security::TlsFiles tls;   // mbaps://
    bool verbose = false;
};

// TARGET (the first positional argument), --unit, --timeout, --retries, --decode, --json,
// --cert, --key, --ca, -v.
void add_client_options(CLI::App& command, ClientOptions& options);

// Registers a client command NAME with TARGET and the shared flags; `run` is called with its
// options when the command line chose it. `Options` has a ClientOptions member `client`. The
// command's own arguments are added to the returned subcommand.
template <class Options>
std::pair<CLI::App*, std::shared_ptr<Options>> add_client_command(
    CLI::App& app, CommandRunner& runner, const std::string& name, const std::string& description,
    const std::string& footer, int (*run)(const Options&)) {
    auto [command, options] = add_command<Options>(app, runner, name, description, footer, run);
    add_client_options(*command, options->client);
    return {command, options};
}

// Lets a duration option take a unit as well, 250ms, 1s, 1.5s, 2m, 1h, while a bare number
// keeps the option's unit. The text is rewritten into a number in that unit before the option's
// own checks (ranges) run, so every option keeps its type, default and limits. `whole`: the option
// holds an integer, so 1.5ms is refused rather than rounded to a different value.
enum class DurationUnit { milliseconds, seconds };
CLI::Option* accept_duration_units(CLI::Option* option, DurationUnit bare_unit, bool whole);

// A duration option: a number in `bare_unit`, or a duration with its unit; `check` limits the
// number. An integer option takes whole numbers only. Its default shows in --help.
template <class T>
CLI::Option* add_duration_option(CLI::App& command, const std::string& name, T& value,
                                 const std::string& help, DurationUnit bare_unit,
                                 const CLI::Validator& check) {
    return accept_duration_units(
        command.add_option(name, value, help)->check(check)->capture_default_str(), bare_unit,
        std::is_integral_v<T>);
}

struct FormatOptions {
    std::string type = "u16";
    std::string word_order = "big";
    std::string byte_order = "big";
};

// --type, --word-order, --byte-order.
void add_format_options(CLI::App& command, FormatOptions& options);
protocol::Result<ValueFormat, std::string> parse_format(const FormatOptions& options);

// How a command ends. Text goes to stdout, errors to stderr as one line "mblab NAME: ...". With
// --json, stdout gets exactly one JSON document, errors included. Exit status: 0 done, 1 the
// device answered with an exception or did not answer properly, 2 usage errors and unreachable
// targets.
class CommandOutput {
  public:
    CommandOutput(std::string command, const ClientOptions& options);

    bool json() const { return json_; }
    // The fields every document carries: command, target, unit.
    nlohmann::json& document() { return document_; }

    int usage(const std::string& message);
    int fail(const client::ClientError& error);
    // Prints the document (JSON mode) and returns kExitOk.
    int done();
    // The same, with `print_text` printing the result as text when not in JSON mode.
    int done(const std::function<void()>& print_text);
    // The line on stderr, without ending the command (watch keeps going).
    void warn(const std::string& message) const;

  private:
    int finish(int status);

    std::string command_;
    bool json_;
    nlohmann::json document_;
};

using ClientBody = std::function<int(client::Client& client, CommandOutput& output)>;

// Connects to the target (unit, timeout, retries and frame log as the options say), then runs
// `body`. An unusable option or target and a connection failure end here.
int with_client(const ClientOptions& options, CommandOutput& output, const ClientBody& body);

// Every connection is a descriptor: lifts the soft limit to the hard one so a thousand
// connections fit. The soft limit now in force.
std::size_t raise_descriptor_limit();

}  // namespace mblab::cli
