#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/dut_options.hpp"
#include "cli/report_files.hpp"
#include "cli/stop_signals.hpp"
#include "cli/suite_options.hpp"
#include "cli/tls_options.hpp"
#include "client/raw_link.hpp"
#include "client/target.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/reports.hpp"
#include "load/mix.hpp"
#include "load/plan.hpp"
#include "load/report.hpp"
#include "load/runner.hpp"
#include "transport/serial_url.hpp"
#include "transport/tcp_url.hpp"
#include "web/http_server.hpp"
#include "web/load_html.hpp"
#include "web/load_metrics.hpp"
#include "web/metrics_text.hpp"

// `mblab load TARGET...`: the interoperability test of CTP 8. The protocol tests
// run in a loop on every node at once while a traffic generator loads them; any failure
// anywhere fails the run. Also a load generator for Modbus/TCP servers.
namespace mblab::cli {

namespace {

namespace conf = mblab::conformance;
namespace load = mblab::load;

constexpr auto kLiveStatusPeriod = std::chrono::seconds(1);
constexpr auto kLogStatusPeriod = std::chrono::seconds(10);
// How fresh --metrics is: a scrape sees the counts of at most this long ago.
constexpr auto kMetricsPeriod = std::chrono::seconds(1);

struct LoadOptions {
    std::vector<std::string> targets;
    SuiteOptions choice;
    bool no_tests = false;
    double duration_s = 3600;
    std::size_t connections = 8;
    double rate = 0;
    std::string mix = "fc3:125=70,fc16:10=20,fc1:100=10";
    std::size_t pipeline = 1;
    DutOptions dut;
    std::string metrics;  // --metrics HOST:PORT
    int timeout_ms = 1000;
    std::size_t threads = std::max(1U, std::thread::hardware_concurrency() / 2);
    std::uint64_t seed = 1;
    TextReports reports;
    security::TlsFiles tls;  // mbaps:// nodes
    CLI::App* command = nullptr;
};

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab load: {}\n", message);
    return kExitUsage;
}

// What the nodes declare: a DUT file, then the flags over it (as `mblab conform` takes them).
protocol::Result<conf::Dut, std::string> declared_dut(const LoadOptions& options) {
    conf::Dut dut;
    conf::DeclarationSources unreported("defaults");
    GivenFlags given(*options.command, unreported);
    if (auto error = options.dut.declare(dut, given); !error.empty()) return error;
    return dut;
}

protocol::Result<load::LoadTarget, std::string> make_target(const std::string& text,
                                                            std::chrono::milliseconds timeout,
                                                            const security::TlsFiles& tls) {
    if (transport::is_serial_url(text)) {
        auto parsed = client::parse_target(text);
        if (!parsed) return parsed.error();
        load::LoadTarget target;
        target.url = parsed->name;
        // A line that cannot be opened is a setup error, as an unreachable TCP node is.
        auto link = client::open_link(*parsed, std::max(timeout, std::chrono::milliseconds(1000)));
        if (!link) return fmt::format("cannot open {}: {}", target.url, link.error().message);
        target.line = std::move(parsed.value());
        return target;
    }
    auto parsed = client::parse_target(text);
    if (!parsed) return parsed.error();
    if (auto error = client::attach_tls(*parsed, tls); !error.empty()) return error;
    const bool secure = parsed->secure;
    auto address =
        secure ? transport::parse_mbaps_address(text) : transport::parse_tcp_address(text);
    if (!address) return address.error();
    auto endpoints = transport::resolve_tcp_address(text, *address);
    if (!endpoints) return endpoints.error();
    load::LoadTarget target;
    target.url = parsed->name;
    target.tls = parsed->tcp->tls;
    // CTP 8.3 loads devices that work; one that cannot be reached is a setup error. Every
    // connection goes to the first address that answered.
    std::string why;
    for (const auto& endpoint : *endpoints) {
        client::Endpoint one = *parsed->tcp;
        one.host = endpoint.address().to_string();
        auto link = client::RawLink::connect(one, timeout);
        if (!link) {
            why = link.error().message;
            continue;
        }
        std::memcpy(&target.address, endpoint.data(), endpoint.size());
        target.address_size = static_cast<socklen_t>(endpoint.size());
        return target;
    }
    return fmt::format("cannot connect to {}: {}", target.url, why);
}

// With a line among the nodes, the unit must be a serial address (1 unless declared).
std::optional<std::string> check_line_unit(const LoadOptions& options, const load::LoadPlan& plan,
                                           conf::Dut& dut) {
    const auto line = std::find_if(plan.targets.begin(), plan.targets.end(),
                                   [](const load::LoadTarget& target) { return target.line; });
    if (line == plan.targets.end()) return std::nullopt;
    return conf::settle_serial_unit(dut, options.dut.unit_declared(*options.command), line->url);
}

protocol::Result<load::LoadPlan, std::string> make_plan(const LoadOptions& options) {
    load::LoadPlan plan;
    auto& s = plan.settings;
    s.duration = std::chrono::milliseconds(std::llround(options.duration_s * 1000));
    s.connections = options.connections;
    s.rate = options.rate;
    s.pipeline = options.pipeline;
    s.timeout = std::chrono::milliseconds(options.timeout_ms);
    s.threads = options.threads;
    s.seed = options.seed;
    s.tests = !options.no_tests;

    std::set<std::string> seen;
    for (const auto& text : options.targets) {
        auto target = make_target(text, s.timeout, options.tls);
        if (!target) return target.error();
        if (!seen.insert(target->url).second) {
            return fmt::format("{} is given twice; each node is one device", target->url);
        }
        plan.targets.push_back(std::move(target.value()));
    }
    auto dut = declared_dut(options);
    if (!dut) return dut.error();
    if (auto error = check_line_unit(options, plan, *dut)) return *error;
    if (s.tests) {
        std::vector<conf::Suite> suites;
        std::string error;
        if (!options.choice.choose({"policy-2.1"}, suites, error)) return error;
        auto added = load::add_protocol_tests(plan, suites, *dut, {});
        if (!added) return added.error();
    }
    if (s.connections > 0) {
        auto mix = load::parse_mix(options.mix);
        if (!mix) return mix.error();
        load::add_mix(plan, *mix, *dut);
    }
    if (plan.test_exchanges == 0 && s.connections == 0) {
        return std::string(
            "nothing to run: no protocol test applies and --connections is 0 (see --case, "
            "--suite, --connections)");
    }
    // One thread per core at most: more would only take turns.
    const std::size_t cores = std::max(1U, std::thread::hardware_concurrency());
    s.threads = std::min({s.threads, std::max<std::size_t>(plan.tcp_connections(), 1), cores});
    return plan;
}

// --metrics: the run's latest status at /metrics, served on threads of their own.
class LoadMetrics {
  public:
    // Any Host: Prometheus scrapes by name, and nothing here changes or tells what a Modbus
    // client could not see.
    explicit LoadMetrics(const load::LoadPlan& plan)
        : plan_(plan), server_(web::GateOptions{{}, {}, 0, {}, true}) {
        latest_.nodes.resize(plan.targets.size());
    }
    bool start(const std::string& address, std::string& error) {
        auto parsed = web::parse_http_address(address, error);
        if (!parsed) {
            error = "--metrics " + error;
            return false;
        }
        server_.routes().get("/metrics", [this](const web::HttpRequest&) {
            std::lock_guard lock(mutex_);
            return web::HttpReply{200, web::load_metrics(plan_, latest_), web::kMetricsContentType};
        });
        auto port = server_.start(*parsed, error);
        if (!port) return false;
        const bool v6 = parsed->host.find(':') != std::string::npos;
        fmt::print("mblab load: metrics at http://{}{}{}:{}/metrics\n", v6 ? "[" : "", parsed->host,
                   v6 ? "]" : "", *port);
        return true;
    }
    void update(const load::LoadStatus& status) {
        std::lock_guard lock(mutex_);
        latest_ = status;
    }

  private:
    const load::LoadPlan& plan_;
    web::HttpServer server_;
    std::mutex mutex_;
    load::LoadStatus latest_;
};

int run_load(const LoadOptions& options) {
    // Before the plan, which connects to every node: a run must not end with "cannot write".
    ReportFiles files;
    std::string error;
    if (!options.reports.check(files, error)) return usage_error(error);
    // A report on standard output has it to itself.
    std::FILE* const console = files.uses_standard_output() ? stderr : stdout;
    auto plan = make_plan(options);
    if (!plan) return usage_error(plan.error());
    std::optional<LoadMetrics> metrics;
    if (!options.metrics.empty()) {
        metrics.emplace(*plan);
        if (!metrics->start(options.metrics, error)) return usage_error(error);
    }
    fmt::print(console, "{}", load::load_header(*plan));
    std::fflush(console);

    raise_descriptor_limit();
    StopSignals::catch_them();
    const bool live = ::isatty(STDERR_FILENO) != 0;
    const auto line_period = live ? kLiveStatusPeriod : kLogStatusPeriod;
    const auto period = metrics ? std::min<std::chrono::milliseconds>(line_period, kMetricsPeriod)
                                : std::chrono::milliseconds(line_period);
    // With --metrics the status comes more often than the line is printed.
    const auto every = static_cast<int>(line_period / period);
    int statuses = 0;
    load::LoadRunner runner(*plan);
    auto result = runner.run(StopSignals::flag(), period, [&](const load::LoadStatus& status) {
        if (metrics) metrics->update(status);
        if (++statuses % every != 0) return;
        fmt::print(stderr, "{}{}{}", live ? "\r\033[K" : "", load::load_status_line(*plan, status),
                   live ? "" : "\n");
        std::fflush(stderr);
    });
    if (live) fmt::print(stderr, "\r\033[K");
    fmt::print(console, "{}", load::load_summary(*plan, result));
    std::fflush(console);

    const std::pair<const std::string&,
                    std::string (*)(const load::LoadPlan&, const load::LoadResult&)>
        reports[] = {{options.reports.json, &load::load_json_report},
                     {options.reports.junit, &load::load_junit_report},
                     {options.reports.html, &web::load_html_report}};
    for (const auto& [path, write] : reports) {
        if (path.empty()) continue;
        if (!files.write(path, write(*plan, result), error)) return usage_error(error);
    }
    return result.verdict() == load::LoadVerdict::Pass ? kExitOk : kExitFailed;
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Interoperability test (CTP 8): the protocol tests in a loop on every "
    "node at once under generated traffic, counting every failure; also a load generator";
constexpr std::string_view kHelp = R"(
Exit status: 0 PASS, 1 FAIL or INCOMPLETE (stopped early), 2 usage error, a file that
cannot be read or written, or a node unreachable at start.
Example: mblab load tcp://10.0.0.5:502 --duration 10m --connections 4
Example: mblab load tcp://127.0.0.1:1502 --duration 1m --metrics 127.0.0.1:9100)";

}  // namespace

void add_load_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_command<LoadOptions>(app, runner, "load", std::string(kSummary),
                                                   help_text(kHelp), run_load);
    options->command = cmd;
    cmd->add_option(
           "targets", options->targets,
           "each node: tcp://HOST[:PORT], rtu+tcp://HOST:PORT, rtu:///dev/ttyX?baud=19200&parity=E "
           "or ascii:///dev/ttyX?...")
        ->required();
    // Down to a millisecond, the run's own resolution; up to a year. The text is seconds by now.
    const CLI::Validator run_length(
        [](const std::string& seconds) -> std::string {
            const double length = std::strtod(seconds.c_str(), nullptr);
            return length >= 0.001 && length <= 31'536'000.0 ? ""
                                                             : "a run lasts from 1ms to a year";
        },
        "");
    add_duration_option(*cmd, "--duration", options->duration_s,
                        "how long to run: seconds, or 10m, 30s, 0.5s, 1500ms, 1h30m (the "
                        "policy's 1h)",
                        DurationUnit::seconds, run_length)
        ->default_str("1h");
    cmd->add_option("--connections", options->connections,
                    "traffic generator connections, spread over the nodes (0: none)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    cmd->add_option("--rate", options->rate,
                    "requests per second over all connections (0: as fast as answered)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--mix", options->mix,
                    "generator requests: fcCODE[:QUANTITY][@ADDRESS][=WEIGHT],... (docs/load.md)")
        ->capture_default_str();
    cmd->add_option("--pipeline", options->pipeline, "requests in flight per generator connection")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    options->dut.add_to(
        *cmd, {"TOML file declaring the nodes (as mblab conform)",
               "unit identifier of the nodes (CTP 6.4; default 1, as every mblab command)",
               "holding registers of the nodes (CTP 6.6; the 9.1.2 read goes past them)", "",
               "the nodes support function code 0x5B (CTP 6.5)", ""});
    add_duration_option(*cmd, "--timeout", options->timeout_ms,
                        "time to wait for each answer: milliseconds, or 250ms, "
                        "2s",
                        DurationUnit::milliseconds, CLI::Range(1, 600000));
    options->choice.add_to(*cmd,
                           "suite whose request/response cases loop, by name or file; "
                           "repeatable (default: policy-2.1)");
    cmd->add_flag("--no-tests", options->no_tests,
                  "no protocol tests: only the traffic generator (a plain load test)");
    cmd->add_option("--threads", options->threads,
                    "worker threads, one per core at most (default: half the cores, leaving the "
                    "rest to devices on this machine)")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    cmd->add_option("--seed", options->seed, "seed of the generator's choices from the mix")
        ->capture_default_str();
    options->reports.add_to(*cmd, "node",
                            "per-node tables and latency histograms (every report file is "
                            "checked before any traffic)");
    cmd->add_option("--metrics", options->metrics,
                    "serve the run's counters and latency histogram in Prometheus text format at "
                    "http://HOST:PORT/metrics while it runs, e.g. 127.0.0.1:9100");
    add_tls_options(*cmd, options->tls, "client's");
}

}  // namespace mblab::cli
