#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "robustness/run_clock.hpp"

// One rung of a storm ladder without I/O: what is due at a given time. A storm is a request
// storm (one request of a function code streamed on a connection of its own, its answers never
// waited for: FC 03 of the monitor's register, and one per other public function code), or a
// connection storm: connections opened and closed again (opens), connections that keep writing
// large reads and never read their answers (slow readers), connections that send part of a
// request and are let go without a FIN (half-open). The rate is requests per second for a request
// storm, connections per second for the others. The owner does what poll() returns and tells the
// core how it went; tests drive it on a manual clock.
namespace mblab::robustness {

enum class StormKind : std::uint8_t {
    Fc03,
    Opens,
    SlowReaders,
    HalfOpen,
    Fc01,
    Fc02,
    Fc04,
    Fc05,
    Fc06,
    Fc08,
    Fc0F,
    Fc10,
    Fc17,
    Fc2B,
    Fc07,
    Fc0B,
    Fc0C,
    Fc11,
    Fc14,
    Fc15,
    Fc16,
    Fc18,
};

// What is said of each storm, in one row: the name --ladder takes ("fc03", "opens", ...), the
// function code a request storm sends (0 for the connection storms), what it does (the report's
// heading; after the function's name for a request storm) and the unit of its rate.
struct StormWords {
    StormKind kind;
    const char* key;
    std::uint8_t function;
    const char* heading;
    const char* unit;
};
const StormWords& storm_words(StormKind kind);
// Every storm's row, in the order of StormKind.
std::span<const StormWords> all_storms();
const char* storm_key(StormKind kind);
bool is_request_storm(StormKind kind);
// The request storms, in the order of their function codes: `--ladder requests:RATES`.
std::vector<StormKind> request_storms();
// "FC 01 (read coils) of one coil, ...": the function table's name before the row's heading.
std::string storm_heading(StormKind kind);
// The rung's phase: "storm 100/s" for FC 03 (the ladder's first storm), "storm opens 10/s",
// "storm fc06 100/s", ...
std::string storm_phase_name(StormKind kind, double rate);

// A storm asked for that could not run: the code is not served, no place may be written, ...
struct StormNotRun {
    StormKind kind = StormKind::Fc03;
    std::string reason;
};

struct LadderRung {
    double rate = 0;  // asked for: requests (request storms) or connections per second
    Clock::time_point begin{};
    Clock::time_point end{};
    std::size_t sent = 0;        // requests written (request storms, slow readers)
    std::size_t answered = 0;    // answers read (request storms)
    std::size_t reconnects = 0;  // request storms: the device closed the storm's connection
    StormKind kind = StormKind::Fc03;
    std::size_t opened = 0;   // connections the storm opened (the connection storms)
    std::size_t refused = 0;  // opens that failed
    // A request storm's coil, input, register or FIFO (none for the codes that name no address,
    // nor for the file record storms): the run sets it.
    std::optional<std::uint16_t> address = {};
};

struct StormAction {
    enum class Do : std::uint8_t {
        OpenStream,      // request storms: open the stream's connection
        SendRequests,    // request storms: write `count` requests on it, as many as it takes
        OpenAndClose,    // opens: a connection opened and closed at once
        OpenSlowReader,  // slow readers: a connection writing large reads as the device takes
                         // them, never reading an answer, held to the rung's end
        OpenHalfOpen,    // half-open: a connection, part of a request, then gone without a FIN
    };
    Do what = Do::OpenStream;
    std::size_t count = 1;
};

class StormCore {
  public:
    StormCore(StormKind kind, double rate, Clock::time_point begin,
              std::chrono::milliseconds duration);

    // The actions due at `now`, in order; none once the rung is over. A request storm: the stream's
    // connection opened when it has none (at most ten opens a second, so a device that closes it
    // gets another), then every request due by now in one go (so the pace holds above a thousand
    // a second). The others: one connection for each due and not yet asked for.
    std::vector<StormAction> poll(Clock::time_point now);
    // How an open the core asked for went.
    void opened(bool ok);
    // Requests written; answers read.
    void sent(std::size_t requests);
    void answered(std::size_t answers);
    // A request storm: the stream's connection closed or broke.
    void stream_lost();
    bool over(Clock::time_point now) const { return now >= until_; }
    // The rung's figures, ended at `now`.
    LadderRung finish(Clock::time_point now);
    const LadderRung& rung() const { return rung_; }

  private:
    std::size_t due(Clock::time_point now) const;

    LadderRung rung_;
    Clock::time_point until_;
    bool stream_open_ = false;
    bool opened_once_ = false;
    Clock::time_point last_open_{};
    std::size_t asked_ = 0;  // connections asked for (the connection storms)
};

}  // namespace mblab::robustness
