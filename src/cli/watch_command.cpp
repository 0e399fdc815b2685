#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/read_query.hpp"

// `mblab watch TARGET KIND ARGS...`: the read of `mblab read`, repeated every --interval, drawn in
// place on a terminal and as plain lines otherwise, counting what went wrong.
namespace mblab::cli {

namespace {

using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_stop = 0;

extern "C" void request_stop(int) {
    g_stop = 1;
}

struct WatchOptions {
    ClientOptions client;
    QueryOptions query;
    int interval_ms = 1000;
    int count = 0;
};

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
    while (g_stop == 0 && Clock::now() < until) {
        std::this_thread::sleep_for(
            std::min<Clock::duration>(until - Clock::now(), std::chrono::milliseconds(50)));
    }
}

int watch(client::Client& client, CommandOutput& out, const WatchOptions& options,
          const ReadQuery& query) {
    Tally tally;
    Screen screen(
        ::isatty(STDOUT_FILENO) != 0,
        fmt::format("{} unit {}: {} every {} ms (Ctrl-C stops)", client.transactor().target(),
                    options.client.unit, describe_query(query), options.interval_ms));
    auto& polls = out.document()["polls"] = nlohmann::json::array();
    const auto interval = std::chrono::milliseconds(options.interval_ms);
    auto next = Clock::now();
    while (g_stop == 0 &&
           (options.count == 0 || tally.polls < static_cast<unsigned>(options.count))) {
        wait_until(next);
        if (g_stop != 0) break;
        next += interval;
        ++tally.polls;
        auto reading = perform_read(client, query);
        nlohmann::json poll = {{"poll", tally.polls}, {"ok", reading.ok()}};
        std::vector<std::string> body;
        if (reading) {
            ++tally.answered;
            poll.update(reading->json);
            body = table_lines(*reading);
        } else {
            // A request the client refuses will be refused on every poll: stop now.
            if (reading.error().kind == client::ErrorKind::Invalid)
                return out.fail(reading.error());
            tally.count(reading.error());
            poll["error"] = {{"kind", client::error_kind_name(reading.error().kind)},
                             {"message", reading.error().message}};
            body.push_back(reading.error().message);
        }
        if (out.json()) {
            polls.push_back(std::move(poll));
        } else {
            screen.draw(tally, body);
        }
    }
    auto& document = out.document();
    document["read"] = describe_query(query);
    document["summary"] = {{"polls", tally.polls},
                           {"answered", tally.answered},
                           {"timeouts", tally.timeouts},
                           {"exceptions", tally.exceptions},
                           {"errors", tally.errors}};
    if (!out.json()) fmt::print("{}\n", tally.text());
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
    g_stop = 0;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    ClientOptions client_options = options.client;
    client_options.probe_units = false;
    return with_client(client_options, output, [&](client::Client& client, CommandOutput& out) {
        return watch(client, out, options, *query);
    });
}

}  // namespace

void add_watch_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<WatchOptions>(
        app, runner, "watch", "Poll a read every --interval and show the values as they change",
        "KIND and its arguments are those of `mblab read`. On a terminal the table is redrawn in\n"
        "place under a line counting polls, timeouts and exceptions; otherwise each poll is\n"
        "printed as \"poll N\" and its table. A poll that fails is counted and polling goes on.\n"
        "Stops after --count polls, or on Ctrl-C; exit status 1 when any poll failed.\n"
        "Example: mblab watch tcp://127.0.0.1:502 holding 0 4 --interval 500",
        run_watch);
    add_query_arguments(*cmd, options->query);
    accept_duration_units(cmd->add_option("--interval", options->interval_ms,
                                          "time between polls: 1000 (ms), 500ms, 2s, 1m "
                                          "(default 1000)")
                              ->check(CLI::Range(1, 86400000)),
                          DurationUnit::milliseconds, true);
    cmd->add_option("--count,-n", options->count, "stop after N polls (default: until Ctrl-C)")
        ->check(CLI::Range(1, 100000000));
}

}  // namespace mblab::cli
