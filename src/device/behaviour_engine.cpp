#include "device/behaviour_engine.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "device/unit_model.hpp"

namespace mblab::device {

namespace {

// After a long stall (a suspended process) at most this many updates are made up for; the
// rest are skipped, so advance() never takes long inside the device's lock.
constexpr std::int64_t kMaxCatchUp = 1000;

double seconds(std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

// Uniform in [0, 1), from the top 53 bits.
double unit_interval(Prng& prng) {
    return static_cast<double>(prng.next() >> 11) * 0x1.0p-53;
}

std::uint32_t register_count(const BehaviourSpec& spec) {
    return spec.points * number_width(spec.layout.type);
}

// The layout an update encodes with: the spec's, its scale 10^sf when a SunSpec scale factor
// register scales it (SunSpec Information Model Specification, "Scale factors"); none while
// that register holds its "not implemented" value 0x8000.
std::optional<NumberLayout> layout_now(const BehaviourSpec& spec, const UnitModel& unit) {
    if (!spec.scale_factor_at) return spec.layout;
    const auto& bank = unit.bank(spec.bank);
    const std::uint16_t word = bank.at(bank.find(*spec.scale_factor_at, 1).index);
    if (word == 0x8000) return std::nullopt;
    NumberLayout layout = spec.layout;
    layout.scale = std::pow(10.0, static_cast<std::int16_t>(word));
    return layout;
}

}  // namespace

BehaviourEngine::BehaviourEngine(const std::vector<BehaviourSpec>& specs, std::uint64_t seed) {
    behaviours_.reserve(specs.size());
    std::uint64_t index = 0;
    for (const auto& spec : specs) {
        // One stream per behaviour, so adding a behaviour does not change the others' draws.
        Running running{spec, {}, {}, {}, Prng(seed + 0x9E3779B97F4A7C15ULL * ++index), {}};
        const double first =
            spec.kind == BehaviourKind::RandomWalk || spec.kind == BehaviourKind::Counter
                ? spec.start
                : 0.0;
        running.state.assign(spec.points, first);
        running.words.assign(register_count(spec), 0);
        behaviours_.push_back(std::move(running));
    }
}

BehaviourEngine::Clock::time_point BehaviourEngine::deadline() const {
    if (behaviours_.empty()) return Clock::time_point::max();
    if (!started_) return Clock::time_point::min();
    auto next = Clock::time_point::max();
    for (const auto& running : behaviours_)
        next = std::min(next, running.next_update);
    return next;
}

void BehaviourEngine::advance(Clock::time_point now, WallClock::time_point wall, UnitModel& unit) {
    if (!started_) {
        started_ = true;
        start_ = now;
        for (auto& running : behaviours_)
            running.next_update = now;
    }
    const double unix_now = std::chrono::duration<double>(wall.time_since_epoch()).count();
    for (auto& running : behaviours_) {
        if (running.next_update > now) continue;
        const auto interval = running.spec.interval;
        const auto behind = (now - running.next_update) / interval;
        if (behind > kMaxCatchUp) running.next_update += (behind - kMaxCatchUp) * interval;
        bool changed = false;
        while (running.next_update <= now) {
            const auto at = running.next_update;
            changed =
                update(running, at, seconds(at - start_), unix_now - seconds(now - at), unit) ||
                changed;
            running.next_update += interval;
        }
        if (!changed) continue;
        auto& bank = unit.bank(running.spec.bank);
        const auto span =
            bank.find(running.spec.address, static_cast<std::uint32_t>(running.words.size()));
        for (std::size_t i = 0; i < running.words.size(); ++i)
            bank.at(span.index + static_cast<std::uint32_t>(i)) = running.words[i];
    }
}

bool BehaviourEngine::update(Running& running, Clock::time_point at, double elapsed,
                             double unix_time, UnitModel& unit) {
    const auto& spec = running.spec;
    if (spec.kind == BehaviourKind::Follow) return follow(running, at, unit);
    const auto layout = layout_now(spec, unit);
    if (!layout) return false;
    const double span = spec.max - spec.min;
    const double cycle = seconds(spec.period);
    for (std::uint32_t point = 0; point < spec.points; ++point) {
        double& value = running.state[point];
        switch (spec.kind) {
            case BehaviourKind::Constant:
                value = spec.value;
                break;
            case BehaviourKind::Ramp:
                value = spec.min + span * (std::fmod(elapsed, cycle) / cycle);
                break;
            case BehaviourKind::Sine:
                value = spec.min + span / 2 +
                        span / 2 * std::sin(2 * std::numbers::pi * elapsed / cycle);
                break;
            case BehaviourKind::RandomWalk:
                // The first update shows the start value itself.
                if (elapsed > 0) {
                    value = std::clamp(value + spec.step * (2 * unit_interval(running.prng) - 1),
                                       spec.min, spec.max);
                }
                break;
            case BehaviourKind::Random:
                value = spec.min + span * unit_interval(running.prng);
                break;
            case BehaviourKind::Counter:
                if (elapsed > 0) value += spec.step;
                if (value > spec.max) value = spec.wraps ? spec.min : spec.max;
                break;
            case BehaviourKind::Uptime:
                value = elapsed;
                break;
            case BehaviourKind::Timestamp:
                value = unix_time;
                break;
            case BehaviourKind::Follow:
                break;  // handled above
        }
        const auto words = encode_number(value, *layout);
        std::copy(words.view().begin(), words.view().end(),
                  running.words.begin() + point * words.count);
    }
    return true;
}

bool BehaviourEngine::follow(Running& running, Clock::time_point at, UnitModel& unit) {
    const auto& spec = running.spec;
    const auto& source = unit.bank(spec.source_bank);
    const auto found = source.find(spec.source, static_cast<std::uint32_t>(running.words.size()));
    Sample sample{at, std::vector<std::uint16_t>(running.words.size())};
    for (std::size_t i = 0; i < sample.words.size(); ++i)
        sample.words[i] = source.at(found.index + static_cast<std::uint32_t>(i));
    running.history.push_back(std::move(sample));
    // The value shown is the newest sample at least `lag` old; older ones are no longer needed.
    const auto due = at - spec.lag;
    while (running.history.size() > 1 && running.history[1].at <= due)
        running.history.pop_front();
    if (running.history.front().at > due) return false;
    running.words = running.history.front().words;
    return true;
}

}  // namespace mblab::device
