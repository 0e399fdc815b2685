#include "cli/serve_log.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <optional>

#include "cli/number_text.hpp"

namespace mblab::cli {

namespace {

// Below this a rotation would come every few lines.
constexpr std::uint64_t kMinLogSize = 1024;

// "10M", "512k", "1G", "2048": bytes, with an optional k, M or G (powers of 1024) and B or iB.
std::optional<std::uint64_t> parse_size(std::string text) {
    for (const std::string_view suffix : {"iB", "B"}) {
        if (text.size() > suffix.size() && text.ends_with(suffix)) {
            text.resize(text.size() - suffix.size());
            break;
        }
    }
    std::uint64_t scale = 1;
    if (!text.empty()) {
        switch (text.back()) {
            case 'k':
            case 'K':
                scale = 1ULL << 10;
                break;
            case 'M':
                scale = 1ULL << 20;
                break;
            case 'G':
                scale = 1ULL << 30;
                break;
            default:
                break;
        }
        if (scale != 1) text.pop_back();
    }
    const auto count = parse_unsigned(text, (1ULL << 50) / scale);
    if (!count) return std::nullopt;
    return *count * scale;
}

void warn(const std::string& warning) {
    fmt::print(stderr, "mblab serve: --log {}\n", warning);
}

}  // namespace

void add_log_options(CLI::App& command, LogOptions& options) {
    options.option =
        command
            .add_option(
                "--log", options.file,
                "print each request and its answer (time, client, unit, function, address, "
                "quantity, values, exception, latency) on standard error, or append them to "
                "FILE (--log=FILE)")
            ->expected(0, 1)
            ->type_name("[FILE]");
    command.add_option("--log-format", options.format, "text (one line to read) or ndjson")
        ->check(CLI::IsMember({"text", "ndjson"}))
        ->type_name("text|ndjson")
        ->capture_default_str();
    command
        .add_option("--log-max-size", options.max_size,
                    "past this size the --log FILE is moved to FILE.1 (the one before is "
                    "removed) and a new one begun: bytes, or 512k, 10M, 1G")
        ->type_name("SIZE")
        ->capture_default_str();
}

std::unique_ptr<server::TrafficLog> open_traffic_log(const LogOptions& options, bool for_http,
                                                     std::string& error) {
    const auto size = parse_size(options.max_size);
    if (!size || *size < kMinLogSize) {
        error = fmt::format("--log-max-size {}: expected a size from 1k, e.g. 512k, 10M or 1G",
                            options.max_size);
        return nullptr;
    }
    const bool given = options.option && options.option->count() > 0;
    if (!given && !for_http) return nullptr;
    std::optional<server::RotatingFile> out;
    if (given && (options.file.empty() || options.file == "-")) {
        out.emplace(server::RotatingFile::unrotated(STDERR_FILENO, "(standard error)", warn));
    } else if (given) {
        auto file = server::RotatingFile::open(options.file, *size, warn);
        if (!file) {
            error = "--log " + file.error();
            return nullptr;
        }
        out.emplace(std::move(file.value()));
    }
    const auto format =
        options.format == "ndjson" ? server::TrafficFormat::Ndjson : server::TrafficFormat::Text;
    return std::make_unique<server::TrafficLog>(std::move(out), format,
                                                for_http ? server::kTrafficRing : 0);
}

}  // namespace mblab::cli
