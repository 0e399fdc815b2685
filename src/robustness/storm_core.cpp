#include "robustness/storm_core.hpp"

#include <fmt/core.h>

namespace mblab::robustness {

namespace {

constexpr std::chrono::milliseconds kReopenEvery{100};

constexpr StormWords kStorms[] = {
    {StormKind::Fc03, "fc03", "FC 03 of the monitor's register, answers never waited for",
     "requests/s"},
    {StormKind::Opens, "opens", "connections opened and closed at once", "connection opens/s"},
    {StormKind::SlowReaders, "slow-readers",
     "connections writing the largest read as fast as the device takes it, never reading an "
     "answer, held to the rung's end",
     "slow readers/s"},
    {StormKind::HalfOpen, "half-open",
     "connections sending 3 bytes of a request, then gone without a FIN",
     "half-open connections/s"},
};
static_assert(kStorms[static_cast<std::size_t>(StormKind::HalfOpen)].kind == StormKind::HalfOpen,
              "one row per StormKind, in its order");

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
    if (rung_.kind == StormKind::Fc03) {
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
    if (rung_.kind == StormKind::Fc03) {
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
