#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/read_query.hpp"
#include "cli/stop_signals.hpp"
#include "cli/terminal_style.hpp"
#include "support/json_document.hpp"

// `mblab watch TARGET KIND ARGS...`: the read of `mblab read`, repeated every --interval, drawn in
// place on a terminal and as plain lines otherwise, counting what went wrong; or streamed one
// line per poll as NDJSON or CSV for logging. A watch may run for days: nothing but the last
// poll's values is kept from one poll to the next.
namespace mblab::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct WatchOptions {
    ClientOptions client;
    QueryOptions query;
    int interval_ms = 1000;
    int count = 0;
    std::string format = "text";
};

// "2024-05-01T12:00:00.123Z": UTC, so lines from machines in different zones sort together.
std::string iso_time(std::chrono::system_clock::time_point when) {
    const auto since = when.time_since_epoch();
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since);
    const auto millis = std::chrono::duration_cast<std::chrono::milliseconds>(since - seconds);
    const std::time_t t = static_cast<std::time_t>(seconds.count());
    std::tm utc{};
    ::gmtime_r(&t, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
    return fmt::format("{}.{:03}Z", text, millis.count());
}

// RFC 4180: a field with a separator, a quote or a line break is quoted, quotes doubled.
std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) {
        quoted += c;
        if (c == '"') quoted += '"';
    }
    return quoted + "\"";
}

bool is_bit_kind(ReadKind kind) {
    return kind == ReadKind::Coils || kind == ReadKind::Discretes;
}

// CSV needs its columns before the first poll answers, so only the kinds whose answer has a shape
// known from the request qualify; the others (a FIFO, the event log) vary from poll to poll.
bool has_fixed_columns(ReadKind kind) {
    return is_bit_kind(kind) || kind == ReadKind::Holding || kind == ReadKind::Input;
}

std::string csv_header(const ReadQuery& query) {
    std::string line = "time,poll,error";
    const auto step = is_bit_kind(query.kind)
                          ? 1U
                          : static_cast<unsigned>(registers_per_value(query.format.type));
    for (unsigned i = 0; i < query.count; ++i)
        line += fmt::format(",{}", query.address + i * step);
    return line;
}

// What a terminal shows for a value that changed since the last poll.
constexpr const char* kMarkOn = "\x1b[7m";
constexpr const char* kMarkOff = "\x1b[27m";

struct Tally {
    unsigned polls = 0;
    unsigned answered = 0;
    unsigned timeouts = 0;
    unsigned exceptions = 0;
    unsigned errors = 0;

    void count(const client::ClientError& error) {
        switch (error.kind) {
            case client::ErrorKind::Timeout:
                ++timeouts;
                break;
            case client::ErrorKind::Exception:
                ++exceptions;
                break;
            default:
                ++errors;
                break;
        }
    }
    std::string text() const {
        return fmt::format("{} poll{}: {} answered, {} timeout{}, {} exception{}, {} other error{}",
                           polls, polls == 1 ? "" : "s", answered, timeouts,
                           timeouts == 1 ? "" : "s", exceptions, exceptions == 1 ? "" : "s", errors,
                           errors == 1 ? "" : "s");
    }
};

// Draws each poll: in place with ANSI escapes on a terminal, appended as plain lines otherwise.
class Screen {
  public:
    Screen(bool terminal, std::string title) : terminal_(terminal), title_(std::move(title)) {}

    void draw(const Tally& tally, const std::vector<std::string>& body) {
        std::vector<std::string> lines;
        if (terminal_) {
            lines.push_back(title_);
            lines.push_back(tally.text());
        } else {
            lines.push_back(fmt::format("poll {}", tally.polls));
        }
        lines.insert(lines.end(), body.begin(), body.end());
        std::string out;
        // Back to the first line of the last drawing, then clear everything below it.
        if (terminal_ && drawn_ > 0) out += fmt::format("\x1b[{}F\x1b[J", drawn_);
        for (const auto& line : lines)
            out += line + "\n";
        fmt::print("{}", out);
        std::fflush(stdout);
        drawn_ = lines.size();
    }

  private:
    bool terminal_;
    std::string title_;
    std::size_t drawn_ = 0;
};

// Sleeps until `until` or a stop request, in short steps so Ctrl-C ends the wait promptly.
void wait_until(Clock::time_point until) {
    while (!StopSignals::requested() && Clock::now() < until) {
        std::this_thread::sleep_for(
            std::min<Clock::duration>(until - Clock::now(), std::chrono::milliseconds(50)));
    }
}

// One poll's output line in the streaming formats.
std::string stream_line(const std::string& format, const ReadQuery& query, unsigned poll,
                        const client::CallResult<Reading>& reading) {
    const std::string time = iso_time(std::chrono::system_clock::now());
    if (format == "ndjson") {
        nlohmann::json line = {{"time", time}, {"poll", poll}, {"ok", reading.ok()}};
        if (reading) {
            line.update(reading->json);
        } else {
            line["error"] = {{"kind", client::error_kind_name(reading.error().kind)},
                             {"message", reading.error().message}};
        }
        return json_document(line, -1);
    }
    std::string line = fmt::format("{},{},", time, poll);
    if (!reading) {
        line += csv_field(reading.error().message);
        for (unsigned i = 0; i < query.count; ++i)
            line += ',';
        return line;
    }
    for (const auto& row : reading->rows)
        line += "," + csv_field(is_bit_kind(query.kind) ? row[1] : row[2]);
    return line;
}

int watch(client::Client& client, CommandOutput& out, const WatchOptions& options,
          const ReadQuery& query) {
    Tally tally;
    const bool terminal = ::isatty(STDOUT_FILENO) != 0;
    const bool streaming = options.format != "text";
    const bool highlight = !streaming && styles_wanted(STDOUT_FILENO);
    Screen screen(terminal, fmt::format("{} unit {}: {} every {} ms (Ctrl-C stops)",
                                        client.transactor().target(), options.client.unit,
                                        describe_query(query), options.interval_ms));
    if (options.format == "csv") {
        fmt::print("{}\n", csv_header(query));
        std::fflush(stdout);
    }
    auto& polls = out.document()["polls"] = nlohmann::json::array();
    // The value cells of the last poll that answered, to mark what changed.
    std::vector<std::string> previous;
    const auto interval = std::chrono::milliseconds(options.interval_ms);
    auto next = Clock::now();
    while (!StopSignals::requested() &&
           (options.count == 0 || tally.polls < static_cast<unsigned>(options.count))) {
        wait_until(next);
        if (StopSignals::requested()) break;
        next += interval;
        ++tally.polls;
        auto reading = perform_read(client, query);
        if (!reading && reading.error().kind == client::ErrorKind::Invalid) {
            // A request the client refuses will be refused on every poll: stop now.
            return out.fail(reading.error());
        }
        if (reading) {
            ++tally.answered;
        } else {
            tally.count(reading.error());
        }
        if (streaming) {
            fmt::print("{}\n", stream_line(options.format, query, tally.polls, reading));
            std::fflush(stdout);
            continue;
        }
        if (out.json()) {
            nlohmann::json poll = {{"poll", tally.polls}, {"ok", reading.ok()}};
            if (reading) {
                poll.update(reading->json);
            } else {
                poll["error"] = {{"kind", client::error_kind_name(reading.error().kind)},
                                 {"message", reading.error().message}};
            }
            polls.push_back(std::move(poll));
            continue;
        }
        std::vector<std::string> body;
        if (reading) {
            std::vector<bool> changed(reading->rows.size(), false);
            std::vector<std::string> values;
            for (std::size_t i = 0; i < reading->rows.size(); ++i) {
                values.push_back(reading->rows[i][2]);
                changed[i] = highlight && i < previous.size() && previous[i] != values.back();
            }
            body = table_lines(*reading, changed, kMarkOn, kMarkOff);
            previous = std::move(values);
        } else {
            body.push_back(reading.error().message);
        }
        screen.draw(tally, body);
    }
    auto& document = out.document();
    document["read"] = describe_query(query);
    document["summary"] = {{"polls", tally.polls},
                           {"answered", tally.answered},
                           {"timeouts", tally.timeouts},
                           {"exceptions", tally.exceptions},
                           {"errors", tally.errors}};
    // The streaming formats keep stdout to their lines; the tally is for whoever watches stderr.
    if (streaming) {
        out.warn(tally.text());
    } else if (!out.json()) {
        fmt::print("{}\n", tally.text());
    }
    if (tally.answered == tally.polls) return out.done();
    return out.fail(
        {client::ErrorKind::BadAnswer,
         fmt::format("{} of {} polls failed", tally.polls - tally.answered, tally.polls),
         std::nullopt});
}

int run_watch(const WatchOptions& options) {
    CommandOutput output("watch", options.client);
    auto query = parse_query(options.query);
    if (!query) return output.usage(query.error());
    if (options.format != "text" && options.client.json) {
        return output.usage(fmt::format(
            "--json prints one document at the end, --format {} a line per poll: give one",
            options.format));
    }
    if (options.format == "csv" && !has_fixed_columns(query->kind)) {
        return output.usage(
            "--format csv takes coils, discretes, holding or input, whose columns are known "
            "before the first answer: use --format ndjson");
    }
    StopSignals::catch_them();
    ClientOptions client_options = options.client;
    client_options.probe_units = false;
    return with_client(client_options, output, [&](client::Client& client, CommandOutput& out) {
        return watch(client, out, options, *query);
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Poll a read every --interval and show the values as they change";
constexpr std::string_view kHelp = R"(
KIND and its arguments are those of `mblab read`. On a terminal the table is redrawn in
place under a line counting polls, timeouts and exceptions; otherwise each poll is
printed as "poll N" and its table. A poll that fails is counted and polling goes on.
With --format ndjson or csv each poll is one line on stdout, written as it comes: a
JSON object, or a CSV row under a header of addresses, each starting with the time
(ISO 8601, UTC); the tally goes to stderr. On a terminal a value that changed since
the last poll is shown in reverse video (not when NO_COLOR is set).
ADDR is a 0-based PDU offset, as for `mblab read` (--base 1, 4x00001).
Stops after --count polls, or on Ctrl-C. Exit status: 0 every poll answered, 1 a poll
failed, 2 usage error or unreachable target.
Example: mblab watch tcp://127.0.0.1:502 holding 0 4 --interval 500)";

}  // namespace

void add_watch_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<WatchOptions>(
        app, runner, "watch", std::string(kSummary), help_text(kHelp), run_watch);
    add_query_arguments(*cmd, options->query);
    accept_duration_units(cmd->add_option("--interval", options->interval_ms,
                                          "time between polls: 1000 (ms), 500ms, 2s, 1m "
                                          "(default 1000)")
                              ->check(CLI::Range(1, 86400000)),
                          DurationUnit::milliseconds, true);
    cmd->add_option("--count,-n", options->count, "stop after N polls (default: until Ctrl-C)")
        ->check(CLI::Range(1, 100000000));
    cmd->add_option("--format", options->format,
                    "text: a table per poll (default); ndjson or csv: one line per poll, with "
                    "its time, for logs and scripts")
        ->check(CLI::IsMember({"text", "ndjson", "csv"}));
}

}  // namespace mblab::cli
