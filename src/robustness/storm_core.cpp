#include "robustness/storm_core.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "protocol/function_table.hpp"

namespace mblab::robustness {

namespace {

constexpr std::chrono::milliseconds kReopenEvery{100};

constexpr const char* kRequests = "requests/s";
// What the writes of one value do: the same for a single and a multiple write.
constexpr const char* kCoilBack = "writing one coil's own value back";
constexpr const char* kRegisterBack = "writing one register's own value back";
// FC 07, 0B, 0C, 11 carry no field ([APP] 6.7, 6.9, 6.10, 6.13).
constexpr const char* kBare = "alone: the request is its function code";

// A request storm's heading is followed by ", answers never waited for".
constexpr StormWords kStorms[] = {
    {StormKind::Fc03, "fc03", 0x03, "of the monitor's register", kRequests},
    {StormKind::Opens, "opens", 0, "connections opened and closed at once", "connection opens/s"},
    {StormKind::SlowReaders, "slow-readers", 0,
     "connections writing the largest read as fast as the device takes it, never reading an "
     "answer, held to the rung's end",
     "slow readers/s"},
    {StormKind::HalfOpen, "half-open", 0,
     "connections sending 3 bytes of a request, then gone without a FIN",
     "half-open connections/s"},
    {StormKind::Fc01, "fc01", 0x01, "of one coil", kRequests},
    {StormKind::Fc02, "fc02", 0x02, "of one input", kRequests},
    {StormKind::Fc04, "fc04", 0x04, "of one register", kRequests},
    {StormKind::Fc05, "fc05", 0x05, kCoilBack, kRequests},
    {StormKind::Fc06, "fc06", 0x06, kRegisterBack, kRequests},
    {StormKind::Fc08, "fc08", 0x08, "sub-function 0000 (return query data)", kRequests},
    {StormKind::Fc0F, "fc0f", 0x0F, kCoilBack, kRequests},
    {StormKind::Fc10, "fc10", 0x10, kRegisterBack, kRequests},
    {StormKind::Fc17, "fc17", 0x17, "reading one register and writing its own value back",
     kRequests},
    {StormKind::Fc2B, "fc2b", 0x2B, "MEI 0E (read device identification), basic objects",
     kRequests},
    {StormKind::Fc07, "fc07", 0x07, kBare, kRequests},
    {StormKind::Fc0B, "fc0b", 0x0B, kBare, kRequests},
    {StormKind::Fc0C, "fc0c", 0x0C, kBare, kRequests},
    {StormKind::Fc11, "fc11", 0x11, kBare, kRequests},
    {StormKind::Fc14, "fc14", 0x14, "of one register of record 0 of a file that answered",
     kRequests},
    {StormKind::Fc15, "fc15", 0x15, "writing one file record register's own value back", kRequests},
    {StormKind::Fc16, "fc16", 0x16, "AND FFFF, OR 0000 on one register: its value kept", kRequests},
    {StormKind::Fc18, "fc18", 0x18, "of a FIFO queue that answered", kRequests},
};

constexpr bool one_row_per_kind_in_order() {
    for (std::size_t i = 0; i < std::size(kStorms); ++i) {
        if (static_cast<std::size_t>(kStorms[i].kind) != i) return false;
    }
    return true;
}
static_assert(one_row_per_kind_in_order(), "one row per StormKind, in its order");

}  // namespace

std::span<const StormWords> all_storms() {
    return kStorms;
}

const StormWords& storm_words(StormKind kind) {
    return kStorms[static_cast<std::size_t>(kind)];
}

const char* storm_key(StormKind kind) {
    return storm_words(kind).key;
}

bool is_request_storm(StormKind kind) {
    return storm_words(kind).function != 0;
}

std::vector<StormKind> request_storms() {
    std::vector<StormKind> out;
    for (const auto& row : kStorms) {
        if (row.function != 0) out.push_back(row.kind);
    }
    std::sort(out.begin(), out.end(), [](StormKind a, StormKind b) {
        return storm_words(a).function < storm_words(b).function;
    });
    return out;
}

std::string storm_heading(StormKind kind) {
    const auto& row = storm_words(kind);
    if (row.function == 0) return row.heading;
    return fmt::format("FC {:02X} ({}) {}, answers never waited for", row.function,
                       protocol::find_function(row.function)->name, row.heading);
}

std::string storm_phase_name(StormKind kind, double rate) {
    if (kind == StormKind::Fc03) return fmt::format("storm {:g}/s", rate);
    return fmt::format("storm {} {:g}/s", storm_key(kind), rate);
}

StormCore::StormCore(StormKind kind, double rate, Clock::time_point begin,
                     std::chrono::milliseconds duration)
    : until_(begin + duration) {
    rung_.kind = kind;
    rung_.rate = rate;
    rung_.begin = begin;
}

std::size_t StormCore::due(Clock::time_point now) const {
    const auto elapsed = std::chrono::duration<double>(now - rung_.begin).count();
    return static_cast<std::size_t>(rung_.rate * elapsed);
}

std::vector<StormAction> StormCore::poll(Clock::time_point now) {
    std::vector<StormAction> out;
    if (over(now)) return out;
    const std::size_t by_now = due(now);
    if (is_request_storm(rung_.kind)) {
        if (!stream_open_ && (!opened_once_ || now - last_open_ >= kReopenEvery)) {
            opened_once_ = true;
            last_open_ = now;
            out.push_back({StormAction::Do::OpenStream, 1});
            // The requests follow the open in the same turn, if it succeeds.
            if (by_now > rung_.sent)
                out.push_back({StormAction::Do::SendRequests, by_now - rung_.sent});
            return out;
        }
        if (stream_open_ && by_now > rung_.sent)
            out.push_back({StormAction::Do::SendRequests, by_now - rung_.sent});
        return out;
    }
    if (by_now <= asked_) return out;
    const auto what = rung_.kind == StormKind::Opens         ? StormAction::Do::OpenAndClose
                      : rung_.kind == StormKind::SlowReaders ? StormAction::Do::OpenSlowReader
                                                             : StormAction::Do::OpenHalfOpen;
    out.push_back({what, by_now - asked_});
    asked_ = by_now;
    return out;
}

void StormCore::opened(bool ok) {
    if (is_request_storm(rung_.kind)) {
        if (ok && rung_.sent > 0) ++rung_.reconnects;
        stream_open_ = ok;
        return;
    }
    ++(ok ? rung_.opened : rung_.refused);
}

void StormCore::sent(std::size_t requests) {
    rung_.sent += requests;
}

void StormCore::answered(std::size_t answers) {
    rung_.answered += answers;
}

void StormCore::stream_lost() {
    stream_open_ = false;
}

LadderRung StormCore::finish(Clock::time_point now) {
    rung_.end = now;
    return rung_;
}

}  // namespace mblab::robustness
