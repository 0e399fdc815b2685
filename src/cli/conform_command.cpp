#include <fcntl.h>
#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cli/catalogue_listing.hpp"
#include "cli/commands.hpp"
#include "cli/conform_reports.hpp"
#include "cli/dut_options.hpp"
#include "cli/profile_lookup.hpp"
#include "cli/report_files.hpp"
#include "cli/stop_signals.hpp"
#include "cli/suite_options.hpp"
#include "cli/terminal_style.hpp"
#include "cli/tls_options.hpp"
#include "client/target.hpp"
#include "conformance/builtin_device.hpp"
#include "conformance/builtin_mbaps.hpp"
#include "conformance/capture.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/catalogue_paths.hpp"
#include "conformance/console_report.hpp"
#include "conformance/declaration_sources.hpp"
#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "conformance/line_search.hpp"
#include "conformance/procedures.hpp"
#include "conformance/provenance.hpp"
#include "conformance/reports.hpp"
#include "conformance/suite_selection.hpp"
#include "device/profile_paths.hpp"
#include "security/pki.hpp"
#include "security/tls_context.hpp"
#include "web/html_report.hpp"

// `mblab conform [TARGET]`: runs conformance suites against a device, or against the built-in
// reference device when no target is given.
namespace mblab::cli {

namespace {

namespace conf = mblab::conformance;

struct ConformOptions {
    std::string target;
    SuiteOptions choice;
    bool list = false;
    DutOptions dut;
    std::string profile;
    std::string catalogue;
    int timeout_ms = 1000;
    int pipeline = 1;
    int settle_ms = 10;
    ConformReports reports;
    security::TlsFiles tls;  // the tester's certificate on mbaps://
    std::string pki;
    std::string read_only_role;
    std::string write_role;
    std::string sunspec_models;
    CLI::App* command = nullptr;
    const Invocation* invocation = nullptr;
};

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab conform: {}\n", message);
    return kExitUsage;
}

// The built-in device's profile: the default one, a file, or a shipped profile by name.
std::optional<std::filesystem::path> builtin_profile(const std::string& wanted,
                                                     std::string& error) {
    if (wanted.empty()) return device::default_profile_path();
    auto found = find_profile(wanted, error);
    if (!found) error = "--profile: " + error;
    return found;
}

// Flags override the DUT file, which overrides what the built-in device's profile says.
bool declare_dut(const ConformOptions& options, conf::Dut& dut, conf::DeclarationSources& sources,
                 std::string& error) {
    GivenFlags given(*options.command, sources);
    error = options.dut.declare(dut, given);
    if (!error.empty()) return false;
    if (given("--pki", "pki")) dut.security.pki = options.pki;
    if (given("--read-only-role", "read_only_role"))
        dut.security.read_only_role = options.read_only_role;
    if (given("--write-role", "write_role")) dut.security.write_role = options.write_role;
    if (given("--cert", "client_cert")) dut.security.client.cert = options.tls.cert;
    if (given("--key", "client_key")) dut.security.client.key = options.tls.key;
    if (given("--ca", "ca")) dut.security.client.ca = options.tls.ca;
    conf::take_client_files_from_pki(dut, sources);
    given.mark(dut);
    return true;
}

int run_conform(const ConformOptions& options) {
    // As MBLAB_SUNSPEC_MODELS: read where the sunspec suite and the built-in device look.
    if (!options.sunspec_models.empty()) {
        ::setenv("MBLAB_SUNSPEC_MODELS", options.sunspec_models.c_str(), 1);
    }
    std::vector<conf::Suite> suites;
    std::string error;
    if (!options.choice.choose({}, suites, error)) return usage_error(error);
    if (options.list) {
        print_catalogue(suites);
        return kExitOk;
    }
    ReportFiles files;
    if (!options.reports.check(files, error)) return usage_error(error);

    conf::Dut dut;
    conf::DeclarationSources sources("defaults");
    std::string note;
    conf::BuiltinDevice builtin;
    client::Target target;
    std::optional<client::Target> secure;
    conf::BuiltinMbaps builtin_mbaps;
    if (options.target.empty()) {
        for (const char* option : {"--cert", "--key", "--ca", "--pki"}) {
            if (options.command->count(option) > 0) {
                return usage_error(fmt::format(
                    "{} is for mbaps:// targets; the built-in device makes its own lab PKI",
                    option));
            }
        }
        const auto found = builtin_profile(options.profile, error);
        if (!found) return usage_error(error);
        if (auto failed = builtin.start(*found, dut, target); !failed.empty()) {
            return usage_error(failed);
        }
        sources.reset(dut.declared_by);
        // As the user named it: a path of the machine it was built on says nothing to a reader
        // of the report elsewhere.
        note = fmt::format(
            "built-in reference device, profile {}",
            options.profile.empty() ? std::string("reference (shipped)") : options.profile);
    } else {
        auto parsed = client::parse_target(options.target);
        if (!parsed) return usage_error(parsed.error());
        target = std::move(parsed.value());
    }
    if (!declare_dut(options, dut, sources, error)) return usage_error(error);
    // After the declarations, which a --dut file replaces whole: the run's own PKI is not one of
    // them to lose.
    if (options.target.empty() && conf::uses_mbaps(suites)) {
        client::Target secure_target;
        const auto profile = builtin_profile(options.profile, error);
        if (auto failed = builtin_mbaps.start(*profile, dut, secure_target); !failed.empty()) {
            return usage_error(failed);
        }
        note += fmt::format("; over mbaps at {}", secure_target.name);
        for (const char* key : {"pki", "client_cert", "client_key", "ca"})
            sources.set(key, "the lab PKI made for the run");
        secure = std::move(secure_target);
    }
    if (!options.target.empty()) {
        if (auto failed =
                client::attach_tls(target, target.secure ? dut.security.client : options.tls);
            !failed.empty()) {
            return usage_error(failed);
        }
        if (!target.secure && !dut.security.pki.empty() && options.command->count("--pki") > 0) {
            return usage_error("--pki is for mbaps:// targets only");
        }
    }
    if (!target.tcp) {
        const bool declared = options.dut.unit_declared(*options.command);
        if (auto problem = conf::settle_serial_unit(dut, declared, target.name)) {
            return usage_error(*problem);
        }
    }

    conf::EngineOptions engine_options;
    engine_options.timeout = std::chrono::milliseconds(options.timeout_ms);
    engine_options.pipeline_depth = static_cast<std::size_t>(options.pipeline);
    engine_options.settle = std::chrono::milliseconds(options.settle_ms);
    // With a report on standard output, the console report goes to standard error.
    const bool report_out = options.reports.to_stdout();
    const int console_fd = report_out ? STDERR_FILENO : STDOUT_FILENO;
    conf::ConsoleReport console(report_out ? stderr : stdout, stderr, ::isatty(STDERR_FILENO) != 0,
                                styles_wanted(console_fd), terminal_width(console_fd));
    conf::Capture capture;
    conf::Session session(target, dut, engine_options,
                          options.reports.pcap.empty() ? nullptr : &capture, &console);
    if (secure) session.set_secure_target(std::move(*secure));
    StopSignals::catch_them();
    const auto started = std::chrono::system_clock::now();
    client::LinkError link_error;
    if (!session.connect(link_error)) {
        return usage_error(
            fmt::format("cannot connect to {}: {}", target.name, link_error.message));
    }

    console.header(target.name, session.dut(), note);
    conf::Engine engine(session, &console);
    engine.stop_when(StopSignals::flag());
    engine.stop_if_unanswered();
    conf::RunResult result = engine.run(suites, target.name);
    console.summary(result);
    if (options.reports.wanted()) {
        conf::ToolIdentity tool;
        if (options.invocation != nullptr) {
            tool = {options.invocation->version, options.invocation->commit,
                    options.invocation->argv};
        }
        const conf::Provenance provenance =
            conf::make_provenance(tool, session, sources, started, result.interrupted);
        if (!options.reports.write(result, provenance, capture, session.framing(), files, error))
            return usage_error(error);
    }
    // 128 + the signal, as a shell reports a program the signal ended: 130 for SIGINT, 143 for
    // SIGTERM, so a script tells an interrupted run from a failed one.
    if (result.interrupted) return StopSignals::exit_status();
    // A device that answers nothing is not under test: the target or the unit is wrong, or the
    // line is set otherwise than the device.
    if (!result.unanswered.empty()) {
        session.close();
        return usage_error(result.unanswered +
                           conf::line_search_hint(target, session.dut(),
                                                  std::chrono::milliseconds(options.timeout_ms)));
    }
    return result.all_passed() ? kExitOk : kExitFailed;
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Run the conformance suites against a device (tcp://, mbaps://, rtu+tcp://, rtu://, "
    "ascii://); "
    "with no target, against the built-in reference device. Exit status: 0 no case failed, 1 a "
    "case failed, 2 usage error or unreachable target, 130/143 stopped by SIGINT/SIGTERM "
    "(between cases; the reports hold the cases run so far)";

}  // namespace

void add_conform_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation) {
    auto [cmd, options] =
        add_command<ConformOptions>(app, runner, "conform", std::string(kSummary), "", run_conform);
    options->invocation = &invocation;
    options->command = cmd;
    cmd->add_option(
        "target", options->target,
        "the device under test: tcp://HOST[:PORT] (port 502 by default), mbaps://HOST[:PORT] "
        "(Modbus/TCP Security, port 802 by default), rtu+tcp://HOST:PORT, "
        "rtu:///dev/ttyX?baud=19200&parity=E&stop=1 or ascii:///dev/ttyX?...");
    options->choice.add_to(*cmd,
                           "suite to run, by name or TOML file; repeatable (default: "
                           "every shipped suite, policy first)");
    cmd->add_flag("--list", options->list,
                  "print the catalogue of the chosen suites (and cases) and exit");
    options->dut.add_to(*cmd,
                        {"TOML file declaring the device under test (keys as the flags below)",
                         "unit identifier of the DUT (CTP 6.4; default 1, as every mblab command)",
                         "number of holding registers of the DUT (CTP 6.6)",
                         "most registers one FC 03 request may read (CTP 6.6)",
                         "the DUT supports function code 0x5B (CTP 6.5)",
                         "the DUT supports the 0x5B alternate encoding (CTP 6.5)"});
    cmd->add_option("--profile", options->profile,
                    "profile of the built-in reference device (no target only): a TOML file or a "
                    "shipped profile's name (reference, rs485-instrument, ...)");
    cmd->add_option("--sunspec-models", options->sunspec_models,
                    "sunspec suite: folder of SunSpec model definitions (model_*.json), e.g. the "
                    "json/ folder of the official set (default: MBLAB_SUNSPEC_MODELS, else "
                    "mblab's own)")
        ->check(CLI::ExistingDirectory);
    cmd->add_option("--timeout", options->timeout_ms, "milliseconds to wait for each answer")
        ->check(CLI::Range(1, 60000));
    cmd->add_option("--pipeline", options->pipeline,
                    "requests in flight during the register sweep and SEMI scan: a speed option; "
                    "above 1 requests are numbered and paired with answers by transaction id "
                    "(default 1: the policy's requests, one at a time)")
        ->check(CLI::Range(1, 64));
    cmd->add_option("--settle", options->settle_ms,
                    "milliseconds to watch for bytes nobody asked for after each case (a "
                    "duplicate answer, noise between cases; default 10)")
        ->check(CLI::Range(0, 10000));
    add_tls_options(*cmd, options->tls, "tester's (client)");
    cmd->add_option("--pki", options->pki,
                    "mbaps://: a lab PKI directory as mblab pki writes it, for the security "
                    "suite's certificates (client-norole, client-expired, ...); its "
                    "client-Administrator and ca.pem stand in for --cert/--key/--ca");
    cmd->add_option(
        "--read-only-role", options->read_only_role,
        "mbaps://: a role the device lets read holding register 0x0010 and not write it "
        "(its certificate is client-ROLE.pem in --pki)");
    cmd->add_option(
        "--write-role", options->write_role,
        "mbaps://: a role the device lets write holding register 0x0010 (client-ROLE.pem "
        "in --pki)");
    options->reports.add_to(*cmd, "case");
}

}  // namespace mblab::cli
