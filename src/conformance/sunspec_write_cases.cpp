#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <span>
#include <thread>

#include "conformance/catalogue.hpp"
#include "conformance/sunspec_cases.hpp"
#include "conformance/sunspec_probe.hpp"
#include "protocol/exception_code.hpp"

// The SunSpec suite's writing cases. A write that takes proves itself by a different valid value
// read back; the value read first is then written back, so the device is left as it was found.
namespace mblab::conformance {

namespace {

using device::SunSpecType;
using Clock = std::chrono::steady_clock;

Outcome pass(std::string remark) {
    return Outcome{Verdict::Pass, std::move(remark), {}};
}

bool is_numeric(SunSpecType type) {
    return type != SunSpecType::String && type != SunSpecType::Pad &&
           type != SunSpecType::Ipv6addr && type != SunSpecType::Eui48 &&
           type != SunSpecType::Float32 && type != SunSpecType::Float64;
}

bool symbol_of(const device::SunSpecPoint& point, std::uint64_t value) {
    return symbol_name(point, static_cast<double>(value)).has_value();
}

// Values other than the point's own a device should take: another symbol of an enum; one more
// or one less for a number; never the type's "not implemented" value.
std::vector<std::vector<std::uint16_t>> other_values(const SunSpecPointReading& point) {
    const device::SunSpecPoint& def = *point.point;
    const std::uint64_t now = device::sunspec_bits(point.words);
    std::vector<std::vector<std::uint16_t>> values;
    if (device::is_sunspec_enum(def.type) && !def.symbols.empty()) {
        for (const device::SunSpecSymbol& symbol : def.symbols) {
            if (static_cast<std::uint64_t>(symbol.value) != now) {
                values.push_back(
                    device::sunspec_words(static_cast<std::uint64_t>(symbol.value), def.size));
            }
        }
        return values;
    }
    const std::uint64_t mask = def.size >= 4 ? ~std::uint64_t{0} : (1ull << (16 * def.size)) - 1;
    for (std::uint64_t candidate : {(now + 1) & mask, (now - 1) & mask}) {
        auto words = device::sunspec_words(candidate, def.size);
        if (!device::is_not_implemented(def, words)) values.push_back(std::move(words));
    }
    return values;
}

// Reads the point until it holds `wanted` or `patience` has passed.
bool reads_back(SunSpecProbe& probe, const SunSpecPointReading& point,
                const std::vector<std::uint16_t>& wanted, std::chrono::milliseconds patience) {
    const auto deadline = Clock::now() + patience;
    while (true) {
        const auto now = probe.read(point);
        if (now && *now == wanted) return true;
        if (Clock::now() >= deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

// "02, 03 or 04".
std::string one_of(std::span<const protocol::ExceptionCode> codes) {
    std::string text;
    for (std::size_t i = 0; i < codes.size(); ++i) {
        if (i > 0) text += i + 1 == codes.size() ? " or " : ", ";
        text += fmt::format("{:02X}", static_cast<int>(codes[i]));
    }
    return text;
}

// Writes `value`, which the device must refuse, and checks the point kept its value; the
// point's value is put back when the device took it. With `codes`, the refusal must be one of
// those exceptions.
std::optional<std::string> refused(SunSpecProbe& probe, const std::string& name,
                                   const SunSpecPointReading& point,
                                   const std::vector<std::uint16_t>& value,
                                   std::span<const protocol::ExceptionCode> codes = {}) {
    const auto written = probe.write(point.address, value);
    const auto after = probe.read(point);
    if (written) {
        const bool kept = after && *after == point.words;
        const auto restored = kept ? written : probe.write(point.address, point.words);
        return fmt::format("{} acknowledged a write of {:X}{}{}", name, device::sunspec_bits(value),
                           kept ? " without an exception (its value kept)" : " and took it",
                           restored ? "" : " (and refused its first value back)");
    }
    if (written.error().kind != client::ErrorKind::Exception) {
        return name + " written: " + written.error().message;
    }
    if (!codes.empty() &&
        std::find(codes.begin(), codes.end(), written.error().exception) == codes.end()) {
        return name + " answered " + written.error().message + ", which is not " + one_of(codes);
    }
    if (!after) return name + " read after the refused write: " + after.error().message;
    if (*after != point.words) return name + " changed although the write was refused";
    return std::nullopt;
}

// A value for an R point, one of its measurements rather than its ID, L, a scale factor or a
// count: the write must be refused.
std::optional<std::vector<std::uint16_t>> read_only_value(const SunSpecPointReading& point) {
    const device::SunSpecPoint& def = *point.point;
    if (def.writable || !point.implemented || !is_numeric(def.type) || def.name == "ID" ||
        def.name == "L" || def.type == SunSpecType::Sunssf || def.type == SunSpecType::Count) {
        return std::nullopt;
    }
    auto other = other_values(point);
    if (other.empty()) return std::nullopt;
    return other.front();
}

// For an RW enum point, the first value past its symbols that is neither one of them nor "not
// implemented".
std::optional<std::vector<std::uint16_t>> outside_symbols(const SunSpecPointReading& point) {
    const device::SunSpecPoint& def = *point.point;
    if (!def.writable || !device::is_sunspec_enum(def.type) || def.symbols.empty() ||
        !point.implemented) {
        return std::nullopt;
    }
    std::uint64_t bad = 0;
    while (symbol_of(def, bad) ||
           device::is_not_implemented(def, device::sunspec_words(bad, def.size)))
        ++bad;
    return device::sunspec_words(bad, def.size);
}

using BadValue = std::optional<std::vector<std::uint16_t>> (*)(const SunSpecPointReading&);

// Writes each point `bad` has a value for (the first of each model when `one_per_model`): each
// write must be refused and leave the point as it was.
Outcome expect_refusals(Session& session, BadValue bad, bool one_per_model, std::string_view none,
                        std::string_view passed, std::string_view why,
                        std::span<const protocol::ExceptionCode> codes = {}) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    std::size_t tried = 0;
    for (const SunSpecModelReading& model : probe.scan().models) {
        for (const SunSpecPointReading& point : model.points) {
            const auto value = bad(point);
            if (!value) continue;
            ++tried;
            if (auto took = refused(probe, point_name(model.id, point), point, *value, codes)) {
                return probe.fail(*took + std::string(why));
            }
            if (one_per_model) break;
        }
    }
    if (tried == 0) return Outcome{Verdict::NotApplicable, std::string(none), {}};
    return pass(fmt::format(fmt::runtime(passed), tried));
}

}  // namespace

Outcome run_sunspec_rw_points(Session& session, const Case& c) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    const std::chrono::milliseconds patience(param(c, "read_back_ms"));
    std::size_t written = 0;
    std::size_t skipped = 0;
    for (const SunSpecModelReading& model : probe.scan().models) {
        for (const SunSpecPointReading& point : model.points) {
            const device::SunSpecPoint& def = *point.point;
            // On a line, a new DA would move the device away: the line case writes DA.
            const bool address = model.id == 1 && def.name == "DA";
            if (!def.writable || !is_numeric(def.type) ||
                (address && !session.dut().serial_framing.empty())) {
                continue;
            }
            if (!point.implemented) {
                ++skipped;
                continue;
            }
            const std::string name = point_name(model.id, point);
            std::optional<std::vector<std::uint16_t>> taken;
            for (const auto& value : other_values(point)) {
                const auto answer = probe.write(point.address, value);
                if (answer) {
                    taken = value;
                    break;
                }
                if (answer.error().kind != client::ErrorKind::Exception) {
                    return probe.fail(answer.error(), "writing " + name);
                }
            }
            if (!taken) return probe.fail(name + " is RW, but refused every other value tried");
            const bool seen = reads_back(probe, point, *taken, patience);
            const auto restored = probe.write(point.address, point.words);
            if (!seen) {
                return probe.fail(fmt::format("{} took {:X}, but did not read it back within {} ms",
                                              name, device::sunspec_bits(*taken),
                                              patience.count()));
            }
            if (!restored) return probe.fail(restored.error(), "writing back " + name);
            ++written;
        }
    }
    if (written == 0) {
        return Outcome{Verdict::NotApplicable, "no implemented RW point to write", {}};
    }
    return pass(fmt::format("{} RW points written, read back and restored{}", written,
                            skipped ? fmt::format(" ({} not implemented)", skipped) : ""));
}

// The SunSpec Device Information Model Specification 1.1 wants a write to a read-only register
// answered with exception 02, 03 or 04 (the older SunSpec Information Model Specification 1.9
// let a device ignore it): a write acknowledged fails even when the value is kept.
constexpr protocol::ExceptionCode kReadOnlyRefusals[] = {
    protocol::ExceptionCode::IllegalDataAddress, protocol::ExceptionCode::IllegalDataValue,
    protocol::ExceptionCode::ServerDeviceFailure};

Outcome run_sunspec_read_only(Session& session, const Case&) {
    return expect_refusals(session, &read_only_value, true, "no implemented R point to write",
                           "writes to an R point of {} models answered exception 02, 03 or 04, "
                           "values unchanged",
                           "; a write to an R point must answer exception 02, 03 or 04",
                           kReadOnlyRefusals);
}

Outcome run_sunspec_bad_enum(Session& session, const Case&) {
    return expect_refusals(session, &outside_symbols, false, "no implemented RW enum point",
                           "{} RW enum points refused a value outside their symbols",
                           ", which is none of its symbols");
}

Outcome run_sunspec_line(Session& session, const Case& c) {
    if (session.dut().serial_framing.empty()) {
        return Outcome{Verdict::NotApplicable, "DA and broadcast writes are for serial lines", {}};
    }
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    const auto turnaround = std::chrono::milliseconds(session.dut().turnaround_ms.value_or(
        static_cast<std::uint32_t>(param(c, "turnaround_ms"))));
    std::string da;
    for (const SunSpecModelReading& model : probe.scan().models) {
        for (const SunSpecPointReading& point : model.points) {
            const device::SunSpecPoint& def = *point.point;
            if (model.id == 1 && def.name == "DA") {
                // The address it has: writing it again must be taken, and moves nothing.
                if (!point.implemented) return probe.fail("1.DA is not implemented on a line");
                const auto answer = probe.write(point.address, point.words);
                if (!answer) return probe.fail(answer.error(), "writing 1.DA its own value");
                da = fmt::format("1.DA = {} written", point.words[0]);
                continue;
            }
            if (da.empty() || !def.writable || !point.implemented || !is_numeric(def.type)) {
                continue;
            }
            // A broadcast write of another value must be applied, unanswered.
            const std::string name = point_name(model.id, point);
            for (const auto& value : other_values(point)) {
                const auto sent = probe.write(point.address, value, turnaround);
                if (!sent) return probe.fail(sent.error(), "FC 16 to address 0 for " + name);
                const auto now = probe.read(point);
                if (!now) return probe.fail(now.error(), "reading " + name + " after a broadcast");
                if (*now != value) continue;  // a value the point does not take: another one
                const auto restored = probe.write(point.address, point.words);
                if (!restored) return probe.fail(restored.error(), "writing back " + name);
                return pass(
                    fmt::format("{}; a broadcast write of {} applied, unanswered", da, name));
            }
            return probe.fail(fmt::format("{}; no broadcast write of {} was applied", da, name));
        }
    }
    if (da.empty()) return probe.fail("no model 1 with DA");
    return Outcome{Verdict::NotApplicable, da + "; no implemented RW point to broadcast to", {}};
}

}  // namespace mblab::conformance
