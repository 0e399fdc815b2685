#include "cli/client_options.hpp"

#include <fmt/core.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "cli/commands.hpp"
#include "cli/frame_log.hpp"
#include "cli/number_text.hpp"
#include "cli/tls_options.hpp"
#include "client/target.hpp"
#include "client/transactor.hpp"
#include "support/json_document.hpp"

namespace mblab::cli {

std::size_t raise_descriptor_limit() {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return 1024;
    if (limit.rlim_cur < limit.rlim_max) {
        limit.rlim_cur = limit.rlim_max;
        ::setrlimit(RLIMIT_NOFILE, &limit);
        ::getrlimit(RLIMIT_NOFILE, &limit);
    }
    return static_cast<std::size_t>(limit.rlim_cur);
}

void add_client_options(CLI::App& command, ClientOptions& options) {
    command
        .add_option("target", options.target,
                    "the device: tcp://HOST[:PORT] (port 502 by default), "
                    "rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1, ascii:///dev/ttyS0?..., or "
                    "rtu+tcp://HOST:PORT, mbaps://HOST[:PORT] (Modbus/TCP Security, port 802 by "
                    "default; needs --cert, --key, --ca)")
        ->required();
    command.add_option("--unit,-u", options.unit, "unit id (default 1)")->check(CLI::Range(0, 255));
    accept_duration_units(
        command
            .add_option("--timeout", options.timeout_ms,
                        "time to wait for the connection and for each answer: 1000 (ms), 250ms, "
                        "2s (default 1000)")
            ->check(CLI::Range(1, 600000)),
        DurationUnit::milliseconds, true);
    command
        .add_option("--retries", options.retries,
                    "tries again after a timeout or a lost connection, up to N times "
                    "(default 0)")
        ->check(CLI::Range(0, 100));
    command
        .add_option("--decode", options.decode,
                    "print every frame sent and received on stderr: app (PDU fields), frame "
                    "(also MBAP header), bytes (also hex)")
        ->check(CLI::IsMember({"app", "frame", "bytes"}));
    command.add_flag("--json", options.json, "print one JSON document on stdout");
    command.add_flag("--no-probe", options.no_probe,
                     "after a request goes unanswered, do not ask units 1, 255 and 0 which one "
                     "answers (each probe waits up to --timeout)");
    add_tls_options(command, options.tls, "client's");
    command.add_flag("-v,--verbose", options.verbose,
                     "mbaps://: print the TLS version, cipher, server certificate and our role on "
                     "stderr");
}

CLI::Option* accept_duration_units(CLI::Option* option, DurationUnit bare_unit, bool whole) {
    const bool ms = bare_unit == DurationUnit::milliseconds;
    const std::chrono::duration<double> unit =
        ms ? std::chrono::duration<double>(0.001) : std::chrono::duration<double>(1);
    const char* unit_name = ms ? "milliseconds" : "seconds";
    auto rewrite = [unit, unit_name, whole](std::string& text) -> std::string {
        // A bare number is in the option's unit: 0.5 is half of it, as 500us would be for
        // milliseconds. One the duration syntax refuses (1e10) goes to the option untouched, to
        // meet its own limits.
        const bool bare = parse_real(text).has_value();
        if (bare && !parse_duration(text, unit)) return {};
        auto length = parse_duration(text, unit);
        if (!length) {
            return fmt::format(
                "'{}' is not a duration: give e.g. 250ms, 1s, 1.5s or 2m (a number alone is {})",
                text, unit_name);
        }
        const double count = *length / unit;
        if (!whole) {
            if (!bare) text = fmt::format("{}", count);
            return {};
        }
        // 1.1s is 1100.0000000000002 ms in doubles: a hair off a whole number is that number.
        const double rounded = std::round(count);
        if (std::abs(count - rounded) > 1e-6) {
            if (bare && unit < std::chrono::seconds(1)) {
                return fmt::format(
                    "'{}' is not a whole number of {} (a number alone is {}: {}s "
                    "is {:g})",
                    text, unit_name, unit_name, text, *length / unit * 1000);
            }
            return fmt::format("'{}' is not a whole number of {}", text, unit_name);
        }
        text = fmt::format("{:.0f}", rounded);
        return {};
    };
    return option->transform(CLI::Validator(rewrite, "", "duration"))->type_name("DURATION");
}

void add_format_options(CLI::App& command, FormatOptions& options) {
    command
        .add_option("--type,-t", options.type,
                    "register value type: " + std::string(kValueTypeNames) + " (default u16)")
        ->check(CLI::IsMember({"u16", "i16", "u32", "i32", "f32", "f64", "hex", "ascii"}));
    command
        .add_option("--word-order", options.word_order,
                    "big: the first register holds the high word (default); little: the low")
        ->check(CLI::IsMember({"big", "little"}));
    command
        .add_option("--byte-order", options.byte_order,
                    "big: each register's high byte first (default); little: swapped")
        ->check(CLI::IsMember({"big", "little"}));
}

protocol::Result<ValueFormat, std::string> parse_format(const FormatOptions& options) {
    ValueFormat format;
    auto type = parse_value_type(options.type);
    auto words = parse_order(options.word_order);
    auto bytes = parse_order(options.byte_order);
    if (!type) return fmt::format("unknown --type '{}' (one of {})", options.type, kValueTypeNames);
    if (!words || !bytes) return std::string("--word-order and --byte-order take big or little");
    format.type = *type;
    format.word_order = *words;
    format.byte_order = *bytes;
    return format;
}

CommandOutput::CommandOutput(std::string command, const ClientOptions& options)
    : command_(std::move(command)), json_(options.json) {
    document_["command"] = command_;
    document_["target"] = options.target;
    document_["unit"] = options.unit;
}

void CommandOutput::warn(const std::string& message) const {
    fmt::print(stderr, "mblab {}: {}\n", command_, message);
}

int CommandOutput::finish(int status) {
    if (json_) {
        document_["ok"] = status == kExitOk;
        document_["status"] = status;
        fmt::print("{}\n", json_document(document_));
    }
    std::fflush(stdout);
    return status;
}

int CommandOutput::usage(const std::string& message) {
    warn(message);
    document_["error"] = {{"kind", "usage"}, {"message", message}};
    return finish(kExitUsage);
}

int CommandOutput::fail(const client::ClientError& error) {
    warn(error.message);
    nlohmann::json detail = {{"kind", client::error_kind_name(error.kind)},
                             {"message", error.message}};
    if (error.exception) {
        detail["exception"] = {{"code", static_cast<int>(*error.exception)},
                               {"name", protocol::exception_name(*error.exception)}};
    }
    document_["error"] = detail;
    const bool usage =
        error.kind == client::ErrorKind::Invalid || error.kind == client::ErrorKind::Connect;
    return finish(usage ? kExitUsage : kExitFailed);
}

int CommandOutput::done() {
    return finish(kExitOk);
}

int CommandOutput::done(const std::function<void()>& print_text) {
    if (!json_) print_text();
    return done();
}

int with_client(const ClientOptions& options, CommandOutput& output, const ClientBody& body) {
    auto target = client::parse_target(options.target);
    if (!target) return output.usage(target.error());
    output.document()["target"] = target->name;
    if (auto error = client::attach_tls(*target, options.tls); !error.empty()) {
        return output.usage(error);
    }

    std::optional<FrameLog> log;
    if (auto depth = parse_decode_depth(options.decode)) log.emplace(stderr, *depth);
    client::TransactionOptions transaction;
    transaction.unit = static_cast<std::uint8_t>(options.unit);
    transaction.timeout = std::chrono::milliseconds(options.timeout_ms);
    transaction.retries = static_cast<unsigned>(options.retries);
    transaction.probe_units = options.probe_units && !options.no_probe;
    const auto timeout = transaction.timeout;
    client::Transactor transactor(
        target->name, [&target, timeout] { return client::open_link(*target, timeout); },
        transaction, log ? &*log : nullptr);
    if (auto connected = transactor.connect(); !connected) return output.fail(connected.error());
    if (options.verbose) {
        if (const auto* peer = transactor.tls_peer()) output.warn("TLS: " + describe_tls(*peer));
    }
    client::Client client(transactor);
    return body(client, output);
}

}  // namespace mblab::cli
