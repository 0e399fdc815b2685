#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/conform_reports.hpp"
#include "cli/report_files.hpp"
#include "cli/terminal_style.hpp"
#include "conformance/capture.hpp"
#include "conformance/client_attach.hpp"
#include "conformance/client_declarations_file.hpp"
#include "conformance/client_exam_line.hpp"
#include "conformance/client_exam_run.hpp"
#include "conformance/console_report.hpp"
#include "conformance/provenance.hpp"
#include "conformance/reports.hpp"
#include "support/json_document.hpp"
#include "transport/serial_url.hpp"
#include "transport/tcp_url.hpp"
#include "web/client_html_report.hpp"

// `mblab conform-client [--listen URL] -- CMD ARGS...`: grades a Modbus client (master) the way
// conform grades a device, with an examiner device that plays it one scenario per run.
namespace mblab::cli {

namespace {

namespace conf = mblab::conformance;

struct ConformClientOptions {
    std::string listen = "tcp://127.0.0.1:0";
    std::vector<std::string> command;
    int unit = 1;
    int timeout_ms = 0;
    int retries = 0;
    bool pipelining = false;
    bool broadcast = false;
    std::string declare;
    int address = 100;
    int count = 2;
    std::string error_pattern;
    std::string value_pattern;
    std::vector<std::string> cases;
    ConformReports reports;  // checked as conform checks them; written below
    std::string pki;
    bool attach = false;
    int attach_wait_ms = 60000;
    CLI::App* app = nullptr;
    const Invocation* invocation = nullptr;
};

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab conform-client: {}\n", message);
    return kExitUsage;
}

std::optional<std::string> bad_regex(const std::string& option, const std::string& pattern) {
    try {
        std::regex checked(pattern);
    } catch (const std::regex_error& error) {
        return option + ": not a regular expression: " + error.what();
    }
    return std::nullopt;
}

std::string declared_text(const conf::ClientDeclarations& declared) {
    std::string text = fmt::format("unit {}, registers {}..{}", declared.unit, declared.address,
                                   declared.address + declared.count - 1);
    text += declared.timeout ? fmt::format(", timeout {} ms", declared.timeout->count())
                             : ", timeout undeclared";
    text +=
        declared.retries ? fmt::format(", retries {}", *declared.retries) : ", retries undeclared";
    if (declared.pipelining) text += ", pipelining";
    if (declared.broadcast) text += ", broadcasts";
    text += declared.error_pattern.empty() ? "; errors by exit status"
                                           : "; errors by pattern /" + declared.error_pattern + "/";
    return text;
}

// conform's JSON report, naming this command and what the client declared instead of a device.
std::string client_json(const conf::RunResult& result, const conf::ClientDeclarations& declared) {
    auto report = nlohmann::json::parse(conf::json_report(result));
    report["tool"] = "mblab conform-client";
    report.erase("dut");
    nlohmann::json client = {{"unit", declared.unit},
                             {"address", declared.address},
                             {"count", declared.count},
                             {"pipelining", declared.pipelining},
                             {"broadcast", declared.broadcast},
                             {"error_pattern", declared.error_pattern},
                             {"value_pattern", declared.value_pattern}};
    client["timeout_ms"] =
        declared.timeout ? nlohmann::json(declared.timeout->count()) : nlohmann::json();
    client["retries"] = declared.retries ? nlohmann::json(*declared.retries) : nlohmann::json();
    report["client"] = client;
    return json_document(report) + "\n";
}

// conform's JUnit report, its <testsuites> named for this command.
std::string client_junit(const conf::RunResult& result) {
    auto report = conf::junit_report(result);
    const std::string_view conform = "<testsuites name=\"mblab conform ";
    if (const auto at = report.find(conform); at != std::string::npos)
        report.insert(at + conform.size() - 1, "-client");
    return report;
}

// The file's declarations (--declare), each flag given on the command line put over them.
std::optional<std::string> declare(const ConformClientOptions& options,
                                   conf::ClientDeclarations& declared) {
    if (!options.declare.empty()) {
        auto from_file = conf::read_client_declarations(options.declare);
        if (!from_file) return "--declare " + from_file.error();
        declared = std::move(*from_file);
    }
    const auto given = [&](const char* flag) { return options.app->count(flag) > 0; };
    if (given("--client-unit")) declared.unit = static_cast<std::uint8_t>(options.unit);
    if (given("--address")) declared.address = static_cast<std::uint16_t>(options.address);
    if (given("--count")) declared.count = static_cast<std::uint16_t>(options.count);
    if (given("--client-timeout")) declared.timeout = std::chrono::milliseconds(options.timeout_ms);
    if (given("--client-retries")) declared.retries = static_cast<unsigned>(options.retries);
    if (given("--client-pipelining")) declared.pipelining = options.pipelining;
    if (given("--client-broadcast")) declared.broadcast = options.broadcast;
    if (given("--error-pattern")) declared.error_pattern = options.error_pattern;
    if (given("--value-pattern") && !options.value_pattern.empty())
        declared.value_pattern = options.value_pattern;
    for (const auto& [option, pattern] : {std::pair{"--error-pattern", declared.error_pattern},
                                          std::pair{"--value-pattern", declared.value_pattern}}) {
        if (auto bad = bad_regex(option, pattern)) return bad;
    }
    return std::nullopt;
}

// The examiner where --listen says: a TCP listener (and its TLS for mbaps) or a serial line.
struct ExamPlace {
    std::unique_ptr<conf::ExamListener> tcp;
    std::unique_ptr<conf::ExamTls> tls;
    std::unique_ptr<conf::ExamLine> line;
    std::string url() const { return tcp ? tcp->url() : line->url(); }
};

std::optional<std::string> open_place(const ConformClientOptions& options, ExamPlace& place) {
    const auto& url = options.listen;
    const bool secure = transport::is_mbaps_url(url);
    if (!options.pki.empty() && !secure) return "--pki is for an mbaps:// --listen";
    if (secure) {
        auto tls = conf::ExamTls::open(options.pki);
        if (!tls) return tls.error();
        place.tls = std::move(*tls);
    }
    if (transport::is_serial_url(url) && !url.starts_with("rtu+tcp:")) {
        auto line = conf::ExamLine::open(url);
        if (!line) return line.error();
        place.line = std::move(*line);
        return std::nullopt;
    }
    auto listener = conf::ExamListener::open(url);
    if (!listener) return listener.error();
    place.tcp = std::move(*listener);
    return std::nullopt;
}

int run_conform_client(const ConformClientOptions& options) {
    if (options.attach && !options.command.empty())
        return usage_error("--attach watches a client that runs by itself: give no command");
    if (!options.attach && options.command.empty())
        return usage_error("give the client's command after --, or --attach");
    conf::ClientExamOptions exam;
    exam.command = options.command;
    exam.attach = options.attach;
    exam.attach_wait = std::chrono::milliseconds(options.attach_wait_ms);
    exam.only = options.cases;
    auto& declared = exam.declared;
    if (auto bad = declare(options, declared)) return usage_error(*bad);
    if (options.attach && !declared.timeout) {
        return usage_error(
            "--attach needs --client-timeout: each scenario watches the client for its tries' "
            "time");
    }
    ReportFiles files;
    std::string error;
    if (!options.reports.check(files, error)) return usage_error(error);
    conf::Capture capture;
    if (!options.reports.pcap.empty()) exam.capture = &capture;
    ExamPlace place;
    if (auto bad = open_place(options, place)) return usage_error(*bad);
    exam.tls = place.tls.get();

    conf::ClientTranscripts transcripts;
    if (!options.reports.html.empty()) exam.transcripts = &transcripts;
    const bool report_out = options.reports.to_stdout();
    const int console_fd = report_out ? STDERR_FILENO : STDOUT_FILENO;
    std::FILE* console_file = report_out ? stderr : stdout;
    conf::ConsoleReport console(console_file, stderr, false, styles_wanted(console_fd),
                                terminal_width(console_fd));
    std::string shown;
    for (const auto& arg : options.command)
        shown += " " + arg;
    if (options.attach) {
        fmt::print(console_file, "mblab conform-client {} --attach\n", place.url());
        fmt::print(console_file,
                   "Attached: each scenario waits up to {} s for the client to poll, then watches "
                   "it until it is quiet for {} ms\n",
                   options.attach_wait_ms / 1000, conf::attach_quiet(declared).count());
    } else {
        fmt::print(console_file, "mblab conform-client {} --{}\n", place.url(), shown);
    }
    if (place.line && place.line->client_url() != place.line->url())
        fmt::print(console_file, "Client's end: {}\n", place.line->client_url());
    if (place.tls) {
        fmt::print(console_file, "PKI: {} ({{ca}} ca.pem, {{cert}} client-norole.pem)\n",
                   place.tls->dir());
    }
    fmt::print(console_file, "Client: {}\n", declared_text(declared));
    std::fflush(console_file);
    const auto started = std::chrono::system_clock::now();
    auto result = place.tcp ? conf::run_client_exam(*place.tcp, exam, &console)
                            : conf::run_client_line_exam(*place.line, exam, &console);
    result.target = place.url();
    console.summary(result);
    conf::Provenance provenance;
    if (options.invocation) {
        provenance.version = options.invocation->version;
        provenance.commit = options.invocation->commit;
        provenance.command_line = options.invocation->argv;
    }
    provenance.started = conf::iso8601_utc(started);
    provenance.finished = conf::iso8601_utc(std::chrono::system_clock::now());
    provenance.declared_by = options.declare.empty() ? "flags" : options.declare;
    provenance.device.reason = "a client is examined, not a device";
    const web::ClientUnderTest client{place.url(), options.command, declared,
                                      place.tls ? place.tls->dir() : ""};
    const std::pair<const std::string*, std::string> reports[] = {
        {&options.reports.json, options.reports.json.empty() ? "" : client_json(result, declared)},
        {&options.reports.junit, options.reports.junit.empty() ? "" : client_junit(result)},
        {&options.reports.html,
         options.reports.html.empty()
             ? ""
             : web::conform_client_html_report(result, provenance, client, transcripts)},
    };
    for (const auto& [path, text] : reports) {
        if (path->empty()) continue;
        if (!ReportFiles::write(*path, text, error)) return usage_error(error);
    }
    // A line's frames on pcapng's user link types (RTU, or ASCII as text); TCP as packets.
    const auto framing = place.line ? place.line->framing() : place.tcp->framing();
    if (!options.reports.pcap.empty() &&
        !conf::write_capture(options.reports.pcap, capture.events(), framing, provenance, error))
        return usage_error(error);
    return result.all_passed() ? kExitOk : kExitFailed;
}

constexpr std::string_view kSummary =
    "Grade a Modbus/TCP, Modbus/TCP Security or serial line client (master): an examiner device "
    "plays it one scenario per run of CMD (no reply, a late answer, wrong transaction id, unit or "
    "slave address, malformed answers, bad CRC or LRC, exceptions, split answers, closed "
    "connections, pipelining, broadcast, certificates to refuse) and judges its requests and its "
    "output. "
    "Exit status: 0 no scenario failed, 1 a scenario failed, 2 usage error";

constexpr std::string_view kFooter = R"(
CMD runs once per scenario, without a shell; in its arguments {host}, {port}, {url}, {unit},
{address} and {count} are filled in. The client should read holding registers {address}..
{address}+{count}-1 of unit {unit} and print their values; the examiner seeds them with 10000 +
address and puts 40000 + address in every answer the client must not take, so its output shows
which answer it used.

Example: mblab conform-client --client-timeout 300ms --client-retries 1 -- mblab read {url}
  holding {address} {count} --unit {unit} --timeout 300 --retries 1 --no-probe

On a line: --listen rtu:///dev/ptmx?baud=19200 makes a pty pair and gives the client its end
in {url}, and as a path and a speed in {device} and {baud} (mbpoll -m rtu -b {baud} {device});
--listen rtu:///dev/ttyUSB0 serves that device (write the client's end in CMD).

Over TLS: --listen mbaps://127.0.0.1:0 makes a lab PKI for the run (or takes --pki DIR) and
fills {ca}, {cert} and {key}; tls.12.1-3 present an expired server certificate, one from an
unknown CA and one for another name, which the client must refuse.

--attach runs no command: a client that polls by itself (a PLC) meets each scenario in turn,
and only its requests are judged (no reply, exceptions, closed connections, certificates); the
scenarios that need its output are N/A.

--listen rtu+tcp://127.0.0.1:0 plays the line scenarios to a client that sends RTU frames over
TCP, as to a serial gateway. See docs/client-conformance.md.)";

}  // namespace

void add_conform_client_command(CLI::App& app, CommandRunner& runner,
                                const Invocation& invocation) {
    auto [cmd, options] =
        add_command<ConformClientOptions>(app, runner, "conform-client", std::string(kSummary),
                                          help_text(kFooter), run_conform_client);
    options->app = cmd;
    options->invocation = &invocation;
    cmd->add_option("--listen", options->listen,
                    "where the examiner listens: tcp://HOST:PORT (port 0: a free one), "
                    "mbaps://HOST:PORT (TLS), rtu+tcp://HOST:PORT (RTU frames over TCP), or the "
                    "serial line it serves: rtu:///DEV?baud=.. or ascii:///DEV (/dev/ptmx: a new "
                    "pty pair, the client's end in {url})")
        ->capture_default_str();
    cmd->add_option("--client-unit", options->unit, "the unit id the client is told to ask")
        ->check(CLI::Range(0, 255))
        ->capture_default_str();
    add_duration_option(*cmd, "--client-timeout", options->timeout_ms,
                        "the client's declared answer timeout (undeclared: scenarios 1 and 2 N/A)",
                        DurationUnit::milliseconds, CLI::Range(1, 600000));
    cmd->add_option("--client-retries", options->retries,
                    "the client's declared retries after a timeout (undeclared: scenario 1 N/A)")
        ->check(CLI::Range(0, 100));
    cmd->add_flag("--client-pipelining", options->pipelining,
                  "the client sends several requests before the answers (scenario 11)");
    cmd->add_flag("--client-broadcast", options->broadcast,
                  "the client can send a broadcast on a line (scenario 9; {unit} is then 0)");
    cmd->add_option("--declare", options->declare,
                    "read the client's declarations from this TOML file (keys named as the "
                    "flags: client-unit, client-timeout in ms, ...); flags override it")
        ->check(CLI::ExistingFile);
    cmd->add_option("--address", options->address, "first holding register the client reads")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    cmd->add_option("--count", options->count, "how many registers it reads")
        ->check(CLI::Range(1, 125))
        ->capture_default_str();
    cmd->add_option("--error-pattern", options->error_pattern,
                    "the client signals an error by printing this (ECMAScript regex); default: by "
                    "a non-zero exit status");
    cmd->add_option("--value-pattern", options->value_pattern,
                    "what a value looks like in its output (regex; group 1 or the match is read as "
                    "a decimal or 0x number); default: every number");
    cmd->add_option("--case", options->cases,
                    "run only this scenario (tcp.3) or group (tcp.6); repeatable");
    options->reports.add_to(*cmd, "scenario");
    cmd->add_flag("--attach", options->attach,
                  "run no command: wait for a client that polls by itself (a PLC) and play it "
                  "each scenario in turn, judging only its requests (needs --client-timeout)");
    add_duration_option(*cmd, "--attach-wait", options->attach_wait_ms,
                        "--attach: how long each scenario waits for the client's first request",
                        DurationUnit::milliseconds, CLI::Range(100, 3600000));
    cmd->add_option("--pki", options->pki,
                    "mbaps: the lab PKI (a directory mblab pki wrote) whose certificates the "
                    "examiner presents; default: one made for the run")
        ->check(CLI::ExistingDirectory);
    cmd->add_option("command", options->command, "the client's command and arguments, after --");
}

}  // namespace mblab::cli
