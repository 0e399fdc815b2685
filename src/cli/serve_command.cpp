#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/profile_lookup.hpp"
#include "cli/serve_http.hpp"
#include "cli/serve_line.hpp"
#include "cli/serve_log.hpp"
#include "cli/serve_state.hpp"
#include "cli/serve_stats_line.hpp"
#include "cli/stop_signals.hpp"
#include "cli/tls_options.hpp"
#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "server/behaviour_timer.hpp"
#include "server/gateway.hpp"
#include "server/kept_devices.hpp"
#include "server/rtu_tcp_server.hpp"
#include "server/serial_server.hpp"
#include "server/server_options.hpp"
#include "server/state_keeper.hpp"
#include "server/tcp_server.hpp"
#include "transport/serial_url.hpp"
#include "transport/tcp_url.hpp"

// `mblab serve [PROFILE]`: the reference device over Modbus/TCP until SIGINT or SIGTERM.
namespace mblab::cli {

namespace {

namespace fs = std::filesystem;
using Seconds = std::chrono::duration<double>;

struct ServeOptions {
    std::string profile = "reference";
    std::string listen = "tcp://127.0.0.1:1502";
    // Signed, so that a negative count is refused rather than wrapped into "no limit".
    long long max_connections = static_cast<long long>(server::ServerOptions{}.max_connections);
    double idle_timeout = 60;
    std::vector<std::string> allow;
    long long max_outstanding = static_cast<long long>(server::ServerOptions{}.max_outstanding);
    int frame_timeout_ms = 250;
    int frame_limit_ms = 1000;
    std::string state;
    double save_interval = 10;
    bool stats = false;
    bool durable = false;
    int devices = 1;
    std::string gateway;
    security::TlsFiles tls;  // mbaps://
    HttpOptions http;
    LogOptions log;
};

int usage_error(const std::string& message) {
    report(message);
    return kExitUsage;
}

// A duration option given in seconds. 0 means `zero_means`; anything else must be a finite
// number from a millisecond (a shorter one would round to 0, which means something else) to a
// year (longer ones overflow the clock's arithmetic).
std::optional<std::chrono::milliseconds> seconds_option(const char* name, double seconds,
                                                        const char* zero_means,
                                                        std::string& error) {
    constexpr double kMaxSeconds = 365.0 * 24 * 3600;
    if (seconds == 0) return std::chrono::milliseconds(0);
    if (std::isfinite(seconds) && seconds >= 0.001 && seconds <= kMaxSeconds) {
        return std::chrono::round<std::chrono::milliseconds>(Seconds(seconds));
    }
    error = fmt::format("{} {:g}: expected 0 ({}) or seconds from 0.001 to {:.0f}", name, seconds,
                        zero_means, kMaxSeconds);
    return std::nullopt;
}

server::ServerOptions server_options(const ServeOptions& options, std::string& error) {
    server::ServerOptions out;
    out.max_connections = static_cast<std::size_t>(options.max_connections);
    if (auto idle = seconds_option("--idle-timeout", options.idle_timeout, "never", error)) {
        out.idle_timeout = *idle;
    }
    out.max_outstanding = static_cast<std::size_t>(options.max_outstanding);
    out.partial_frame_timeout = std::chrono::milliseconds(options.frame_timeout_ms);
    out.frame_limit = std::chrono::milliseconds(options.frame_limit_ms);
    for (const auto& entry : options.allow) {
        if (!out.allow.add(entry, error)) break;
    }
    return out;
}

// --cert/--key/--ca, each taken from the profile's [tls] table when the command line does not
// give it; the profile's paths are relative to its file.
security::TlsFiles server_tls_files(const security::TlsFiles& given, const device::Profile& profile,
                                    const std::filesystem::path& profile_path) {
    const auto from_profile = [&](const std::string& file) {
        if (file.empty() || std::filesystem::path(file).is_absolute()) return file;
        return (profile_path.parent_path() / file).lexically_normal().string();
    };
    return {given.cert.empty() ? from_profile(profile.tls.cert) : given.cert,
            given.key.empty() ? from_profile(profile.tls.key) : given.key,
            given.ca.empty() ? from_profile(profile.tls.ca) : given.ca};
}

int run_serve(const ServeOptions& options) {
    std::string error;
    // rtu+tcp:// is a TCP listener whose sessions frame RTU; rtu:// and ascii:// are lines.
    std::optional<transport::SerialUrl> serial;
    if (transport::is_serial_url(options.listen)) {
        auto url = transport::parse_serial_url(options.listen);
        if (!url) return usage_error(url.error());
        serial = std::move(url.value());
    }
    const bool rtu_over_tcp = serial && serial->kind == transport::SerialUrl::Kind::RtuOverTcp;
    if (serial && !rtu_over_tcp && (options.devices != 1 || !options.gateway.empty())) {
        return usage_error("--devices and --gateway need a tcp:// or rtu+tcp:// --listen");
    }
    std::unique_ptr<server::SerialGateway> gateway;
    if (!options.gateway.empty()) {
        auto url = transport::parse_serial_url(options.gateway);
        if (!url) return usage_error(url.error());
        auto made = server::make_gateway(*url);
        if (!made) return usage_error(made.error());
        gateway = std::move(made.value());
    }
    const bool secure = transport::is_mbaps_url(options.listen);
    auto endpoint = serial
                        ? protocol::Result<asio::ip::tcp::endpoint, std::string>(serial->endpoint)
                    : secure ? transport::parse_mbaps_url(options.listen)
                             : transport::parse_tcp_url(options.listen);
    if (!endpoint) return usage_error(endpoint.error());
    if (!secure && !options.tls.empty()) {
        return usage_error("--cert, --key and --ca are for an mbaps:// --listen");
    }
    auto profile_path = find_profile(options.profile, error);
    if (!profile_path) return usage_error(error);
    auto server_config = server_options(options, error);
    if (!error.empty()) return usage_error(error);
    const auto save_period =
        seconds_option("--save-interval", options.save_interval, "only on exit", error);
    if (!save_period) return usage_error(error);
    if (options.durable && options.state.empty())
        return usage_error("--durable needs --state FILE");
    if (options.durable && gateway) {
        return usage_error("--durable keeps a device's writes; a --gateway has none");
    }
    const auto http = plan_http(options.http, error);
    if (!error.empty()) return usage_error(error);
    if (http && (gateway || options.devices != 1)) {
        return usage_error("--http shows one device: not with --gateway or --devices");
    }
    auto first_port = static_cast<unsigned>(endpoint->port());
    if (first_port != 0 && first_port + static_cast<unsigned>(options.devices) - 1 > 65535) {
        return usage_error(fmt::format("{} devices from port {} run past port 65535",
                                       options.devices, first_port));
    }

    server::KeptDevicesOptions kept_options{
        *profile_path, static_cast<std::size_t>(options.devices), options.state, options.durable};
    auto opened = server::KeptDevices::open(kept_options, report);
    if (!opened) return usage_error(opened.error());
    // Closed before the io_context goes at the end (their journals' threads post answers to it).
    auto& kept = **opened;
    auto& first_device = kept.device(0);
    security::SharedContext tls;
    if (secure) {
        auto context = security::make_server_context(
            server_tls_files(options.tls, first_device.declarations().profile(), *profile_path));
        if (!context) return usage_error(context.error());
        tls = std::move(context.value());
    }
    server::StateKeeper* first_keeper = kept.keeper(0);
    // Counts every request for the HTTP side, whatever answers it.
    std::unique_ptr<LiveDevice> live;
    if (http) {
        live = std::make_unique<LiveDevice>(first_device, kept.handler(0));
        write_values_through(*live, first_keeper);
    }
    auto traffic = open_traffic_log(options.log, http.has_value(), error);
    if (!error.empty()) return usage_error(error);
    // The log sees what the client sees: outside the counting, whatever answers.
    std::vector<std::unique_ptr<server::LoggedHandler>> logged;
    const auto answering = [&](std::size_t i) -> device::RequestHandler& {
        if (gateway) return *gateway;
        if (live) return live->handler();
        return kept.handler(i);
    };
    for (std::size_t i = 0; traffic && i < kept.size(); ++i) {
        logged.push_back(
            std::make_unique<server::LoggedHandler>(answering(i), *traffic, options.listen));
    }
    if (live) live->show_traffic(traffic.get());
    auto device_handler = [&](std::size_t i) -> device::RequestHandler& {
        if (traffic) return *logged[i];
        return answering(i);
    };

    std::signal(SIGPIPE, SIG_IGN);
    if (serial && !rtu_over_tcp) {
        return run_serial_line(*serial, kept, device_handler(0), *save_period, live.get(), http);
    }
    // One thread runs every server; without a gateway or a journal nothing else touches the
    // io_context, so it takes no locks. A gateway's or a journal's thread posts answers to it.
    asio::io_context io(gateway || options.durable ? 1 : ASIO_CONCURRENCY_HINT_UNSAFE);
    std::vector<std::unique_ptr<server::TcpServer>> servers;
    std::vector<std::string> urls;
    for (std::size_t i = 0; i < kept.size(); ++i) {
        auto config = server_config;
        auto* device = &kept.device(i);
        config.on_busy_reply = [device](std::uint8_t unit) {
            device->counters().count_busy_reply(unit);
        };
        if (secure) {
            config.tls = tls;
            config.roles =
                std::make_shared<const device::RoleRules>(device->declarations().profile().roles);
            config.on_tls_refused = [](const std::string& reason) {
                fmt::print(stderr, "mblab serve: refused a TLS client: {}\n", reason);
            };
        }
        if (traffic) {
            // What the session answers itself never reaches the handler that logs.
            config.on_own_answer = [log = traffic.get()](const auto& context, auto request,
                                                         auto code) {
                log->record_own_answer(context, request, code);
            };
        }
        device::RequestHandler& handler = device_handler(i);
        servers.push_back(
            rtu_over_tcp
                ? std::make_unique<server::TcpServer>(
                      io, handler, config,
                      server::rtu_session_starter(config, server::device_line_hooks(*device)))
                : std::make_unique<server::TcpServer>(io, handler, std::move(config)));
        auto at = *endpoint;
        if (first_port != 0) at.port(static_cast<std::uint16_t>(first_port + i));
        auto port = servers.back()->start(at);
        if (!port) return usage_error(port.error());
        at.port(*port);
        urls.push_back((rtu_over_tcp ? "rtu+" : "") + transport::format_tcp_url(at, secure));
    }

    std::string where = urls.front();
    if (urls.size() > 1 && first_port != 0) {
        where += fmt::format("..{}", first_port + urls.size() - 1);
    } else {
        for (std::size_t i = 1; i < urls.size(); ++i)
            where += ", " + urls[i];
    }
    if (gateway) {
        fmt::print("mblab serve: gateway on {} to {}; stop with Ctrl-C\n", where, options.gateway);
    } else {
        fmt::print("mblab serve: {} {} on {}, {}; stop with Ctrl-C\n",
                   kept.size() > 1 ? fmt::format("{} {}", kept.size(),
                                                 first_device.declarations().profile().name)
                                   : first_device.declarations().profile().name,
                   kept.size() > 1 ? "devices" : "profile", where,
                   first_device.declarations().addressing(rtu_over_tcp ? device::Link::Serial
                                                                       : device::Link::Tcp));
    }
    std::fflush(stdout);
    const auto connections = [&servers] {
        std::uint64_t open = 0;
        for (const auto& s : servers)
            open += server::ServerStats::read(s->stats().connections_open);
        return open;
    };
    if (live && !live->start(*http, connections, state_saver_for_http(first_keeper), error)) {
        return usage_error(error);
    }

    asio::steady_timer save_timer(io);
    asio::steady_timer stats_timer(io);
    std::vector<std::unique_ptr<server::BehaviourTimer>> behaviours;
    for (std::size_t i = 0; i < kept.size(); ++i) {
        behaviours.push_back(std::make_unique<server::BehaviourTimer>(io, kept.device(i)));
        behaviours.back()->start();
    }
    StatsLine stats_line(servers);
    bool stopping = false;
    if (kept.keeps_state() && save_period->count() > 0) {
        asio::co_spawn(io, every(save_timer, *save_period, stopping, [&] { kept.save_soon(); }),
                       asio::detached);
    }
    if (options.stats) {
        asio::co_spawn(
            io, every(stats_timer, std::chrono::seconds(1), stopping, [&] { stats_line.print(); }),
            asio::detached);
    }
    const auto signals = watch_stop_signals(io, [&] {
        stopping = true;
        for (auto& s : servers)
            s->stop();
        save_timer.cancel();
        stats_timer.cancel();
        for (auto& timer : behaviours)
            timer->stop();
    });
    io.run();
    if (live) live->stop();
    // The gateway's thread posts to `io`: end it while `io` is still there.
    if (gateway) gateway->stop();

    // Every session has ended, so every write the device acknowledged is in it now.
    if (options.stats) {
        stats_line.print();
        stats_line.finish();
    }
    const bool saved = kept.save_all();
    // A journal's thread posts answers to `io`: end it while `io` is still there.
    kept.close();
    return saved ? kExitOk : kExitFailed;
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "run the reference device over Modbus/TCP, TLS (mbaps), RTU, "
    "ASCII or RTU over TCP, or a TCP-to-serial gateway";
constexpr std::string_view kHelp = R"(
Serves until SIGINT or SIGTERM.
Exit status: 0 stopped by SIGINT or SIGTERM, 1 --state could not be saved, 2 usage
error, or a profile, file or address that cannot be used.
Example: mblab serve --listen tcp://0.0.0.0:1502 reference
Example: mblab serve --http 127.0.0.1:8080 (dashboard at http://127.0.0.1:8080/))";

}  // namespace

void add_serve_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_command<ServeOptions>(app, runner, "serve", std::string(kSummary),
                                                    help_text(kHelp), run_serve);
    cmd->add_option("profile", options->profile,
                    "device profile: a TOML file or a shipped profile's name")
        ->capture_default_str();
    cmd->add_option("--listen", options->listen,
                    "address to listen on: tcp://HOST:PORT (port 0: any free port), "
                    "rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1&data=8, ascii:///dev/... "
                    "rtu+tcp://HOST:PORT, or mbaps://HOST:PORT (Modbus/TCP Security, TLS with "
                    "client certificates: needs --cert, --key, --ca; roles from the profile)")
        ->capture_default_str();
    add_tls_options(*cmd, options->tls, "server's");
    cmd->add_option("--gateway", options->gateway,
                    "forward TCP requests to devices on a serial line instead of serving the "
                    "profile: rtu:///dev/ttyUSB0?baud=19200&units=1-247&timeout=1000 (ms)");
    cmd->add_option("--max-connections", options->max_connections,
                    "connections at once; when full the oldest stalled (trickling, not reading), "
                    "else never used, else idle one is closed (0: no limit)")
        ->check(CLI::Range(0LL, 1'000'000LL))
        ->capture_default_str();
    add_duration_option(*cmd, "--idle-timeout", options->idle_timeout,
                        "time without a request before a connection is closed: "
                        "seconds, or 500ms, 5m (0: never)",
                        DurationUnit::seconds, CLI::NonNegativeNumber);
    cmd->add_option("--allow", options->allow,
                    "admit only clients from this address or CIDR network (repeatable)");
    cmd->add_option("--max-outstanding", options->max_outstanding,
                    "requests a connection may have unanswered; more are answered 06 busy")
        ->check(CLI::Range(1LL, 4096LL))
        ->capture_default_str();
    add_duration_option(*cmd, "--frame-timeout", options->frame_timeout_ms,
                        "time an unfinished frame may wait before it is answered 03: "
                        "milliseconds, or 250ms, 1s",
                        DurationUnit::milliseconds, CLI::Range(1, 60000));
    add_duration_option(*cmd, "--frame-limit", options->frame_limit_ms,
                        "time a whole frame may take from its first byte: milliseconds, or 1s; a "
                        "client still sending it then is answered 03 and closed",
                        DurationUnit::milliseconds, CLI::Range(1, 600000));
    cmd->add_option("--state", options->state,
                    "keep the writable data in FILE: restored at start, saved periodically and "
                    "on exit");
    add_duration_option(*cmd, "--save-interval", options->save_interval,
                        "time between saves of --state: seconds, or 500ms, "
                        "5m (0: only on exit)",
                        DurationUnit::seconds, CLI::NonNegativeNumber);
    cmd->add_flag("--durable", options->durable,
                  "with --state: every acknowledged write is in a journal on disk (FILE.journal, "
                  "fdatasync shared by the writes that come together) before its answer is sent, "
                  "so kill -9 loses none; a write that cannot be journaled is answered 04 (500 "
                  "over --http); past 64 MiB of journal the state is saved, whatever "
                  "--save-interval says");
    cmd->add_flag("--stats", options->stats, "print a line of counters on stderr every second");
    add_http_options(*cmd, options->http);
    add_log_options(*cmd, options->log);
    cmd->add_option("--devices", options->devices,
                    "run K devices on consecutive ports from the --listen port")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
}

}  // namespace mblab::cli
