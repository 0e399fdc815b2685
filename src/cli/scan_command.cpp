#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/number_text.hpp"
#include "cli/tls_options.hpp"
#include "client/target.hpp"
#include "conformance/provenance.hpp"
#include "conformance/reports.hpp"
#include "robustness/scan.hpp"
#include "robustness/scan_report.hpp"

// `mblab scan TARGET`: learns what a device answers with requests that change nothing and
// writes the DUT file `mblab conform --dut` reads (docs/scan.md).
namespace mblab::cli {

namespace {

namespace rb = mblab::robustness;

struct ScanCommandOptions {
    std::string target;
    std::string units;  // "1,255,0", "1-247"
    int timeout_ms = 1000;
    std::string output = "dut.toml";
    bool force = false;
    security::TlsFiles tls;
    const Invocation* invocation = nullptr;
};

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab scan: {}\n", message);
    return kExitUsage;
}

// "1,255,0", "1-247", "1,5-9": the units in the order given, each once.
std::optional<std::vector<std::uint8_t>> parse_units(std::string_view text) {
    std::vector<std::uint8_t> units;
    while (!text.empty()) {
        const auto comma = text.find(',');
        const std::string_view item = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
        const auto dash = item.find('-');
        const auto first = parse_unsigned(item.substr(0, dash), 255);
        const auto last =
            dash == std::string_view::npos ? first : parse_unsigned(item.substr(dash + 1), 255);
        if (!first || !last || *last < *first) return std::nullopt;
        for (auto unit = *first; unit <= *last; ++unit) {
            if (std::find(units.begin(), units.end(), unit) == units.end())
                units.push_back(static_cast<std::uint8_t>(unit));
        }
    }
    if (units.empty()) return std::nullopt;
    return units;
}

int run_scan(const ScanCommandOptions& options) {
    const auto started = std::chrono::system_clock::now();
    auto target = client::parse_target(options.target);
    if (!target) return usage_error(target.error());
    if (auto failed = client::attach_tls(*target, options.tls); !failed.empty())
        return usage_error(failed);
    rb::ScanOptions scan_options;
    scan_options.line = client::framing_of(*target) != client::Framing::Mbap;
    // On Modbus/TCP 255 and 0 reach the device itself ([TCPG] 4.4.1.2); a line is swept only
    // when asked, at a timeout for each silent address.
    const std::string units = !options.units.empty() ? options.units
                              : scan_options.line    ? "1"
                                                     : "1,255,0";
    const auto parsed = parse_units(units);
    if (!parsed) {
        return usage_error(fmt::format(
            "--units '{}' is not a list of unit ids and ranges from 0 to 255 (1,255,0 or 1-247)",
            options.units));
    }
    scan_options.units = *parsed;
    if (scan_options.line && std::all_of(parsed->begin(), parsed->end(), [](std::uint8_t unit) {
            return unit == 0 || unit > 247;
        })) {
        return usage_error(fmt::format(
            "on {} a device answers at an address from 1 to 247 (0 is the broadcast): give "
            "--units within 1-247",
            target->name));
    }
    const bool to_stdout = options.output == "-";
    if (!to_stdout && !options.force && std::filesystem::exists(options.output)) {
        return usage_error(fmt::format("{} exists: give --force to replace it, or -o another file",
                                       options.output));
    }
    // Checked before anything is sent, so that a scan is not run for a file that cannot be kept.
    const auto directory = std::filesystem::path(options.output).parent_path();
    if (!to_stdout && !directory.empty() && !std::filesystem::is_directory(directory))
        return usage_error(fmt::format("{}: no such directory", directory.string()));
    std::signal(SIGPIPE, SIG_IGN);
    auto scan =
        rb::scan_target(*target, scan_options, std::chrono::milliseconds(options.timeout_ms));
    if (!scan) return usage_error(scan.error());
    // With the file on stdout, the table goes to stderr so that the file can be piped.
    std::FILE* console = to_stdout ? stderr : stdout;
    fmt::print(console, "mblab scan {}\n{}", target->name, rb::scan_text(*scan));
    rb::ScanOrigin origin;
    origin.target = target->name;
    origin.version = options.invocation != nullptr ? options.invocation->version : "";
    origin.started = conformance::iso8601_utc(started);
    const std::string toml = rb::scan_dut_toml(*scan, origin);
    if (to_stdout) {
        fmt::print("{}", toml);
        return kExitOk;
    }
    std::string failed;
    if (!conformance::write_text_file(options.output, toml, failed)) return usage_error(failed);
    fmt::print(
        console, "wrote {}: check it, then run {}\n", options.output,
        conformance::shell_words({"mblab", "conform", target->name, "--dut", options.output}));
    return kExitOk;
}

constexpr std::string_view kSummary =
    "Learn what a device answers (units, function codes, tables, identification) with requests "
    "that change nothing, and write a DUT file for mblab conform --dut";
constexpr std::string_view kHelp = R"(
Nothing is written to the device: reads, the FC 08 return query data echo, device
identification (FC 2B/0E) and FC 5B get attribute only. Each table's answered range is
found with single reads, then read whole once. The DUT file marks each value
"# learned by mblab scan: ..." and says why the keys it leaves out are not declared.
Exit status: 0 scanned and the file written, 2 usage error, the file exists (without
--force), the target unreachable, or no unit answered.
Example: mblab scan tcp://192.168.1.10:502 -o meter.toml
Example: mblab scan 'rtu:///dev/ttyUSB0?baud=19200' --units 1-247 -o - > dut.toml)";

}  // namespace

void add_scan_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation) {
    auto [cmd, options] = add_command<ScanCommandOptions>(
        app, runner, "scan", std::string(kSummary), help_text(kHelp), run_scan);
    options->invocation = &invocation;
    cmd->add_option("target", options->target,
                    "the device, as for mblab conform: tcp://, "
                    "mbaps://, rtu://, ascii:// or rtu+tcp://")
        ->required();
    cmd->add_option("--units,--unit", options->units,
                    "unit ids to try, in order: 1,255,0 or 1-247 (default 1,255,0 on "
                    "Modbus/TCP, 1 on a serial line); the first that answers is scanned");
    add_duration_option(*cmd, "--timeout", options->timeout_ms,
                        "how long each request waits for its answer: milliseconds, or 250ms, 2s",
                        DurationUnit::milliseconds, CLI::Range(1, 600000));
    cmd->add_option("-o,--output", options->output,
                    "the DUT file to write ('-': stdout, the table then on stderr)")
        ->capture_default_str();
    cmd->add_flag("--force", options->force, "replace the output file when it exists");
    add_tls_options(*cmd, options->tls, "tester's (client)");
}

}  // namespace mblab::cli
