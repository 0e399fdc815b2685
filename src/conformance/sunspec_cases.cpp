#include "conformance/sunspec_cases.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <thread>

#include "conformance/catalogue.hpp"
#include "conformance/sunspec_probe.hpp"

// The SunSpec suite's reading cases: each scans the chain afresh (SunSpecProbe) and judges what
// the SunSpec Device Information Model Specification and the SunSpec Modbus Specification ask of
// it (catalogue/sunspec.toml cites the sections).
namespace mblab::conformance {

namespace {

using device::SunSpecType;

constexpr std::uint16_t kMarker[] = {0x5375, 0x6E53};
constexpr std::uint16_t kCommonLength = 66;
constexpr int kLowestScale = -10;
constexpr int kHighestScale = 10;

Outcome pass(std::string remark) {
    return Outcome{Verdict::Pass, std::move(remark), {}};
}

// PASS, or FAIL with the first few problems.
Outcome judged(SunSpecProbe& probe, const std::vector<std::string>& problems, std::string passed) {
    if (problems.empty()) return pass(std::move(passed));
    std::string text;
    for (std::size_t i = 0; i < problems.size() && i < 5; ++i)
        text += (i == 0 ? "" : "; ") + problems[i];
    if (problems.size() > 5) text += fmt::format(" (and {} more)", problems.size() - 5);
    return probe.fail(text);
}

// Calls visit(model, point) for every point of every model with a definition.
template <class Visit>
void each_point(SunSpecProbe& probe, Visit visit) {
    for (const SunSpecModelReading& model : probe.scan().models) {
        for (const SunSpecPointReading& point : model.points)
            visit(model, point);
    }
}

// What a case that looks at every point found: the points it judged and what was wrong.
struct PointTally {
    std::size_t count = 0;
    std::vector<std::string> problems;
};

// Scans the device and runs check(probe, model, point, tally) on every point, `settle` after the
// scan; the remark counts the points judged ("12 strings ASCII and NUL-padded").
template <class Check>
Outcome judge_points(Session& session, std::string_view counted, Check check,
                     std::chrono::milliseconds settle = {}) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    if (settle.count() > 0) std::this_thread::sleep_for(settle);
    PointTally tally;
    each_point(probe, [&](const SunSpecModelReading& model, const SunSpecPointReading& point) {
        check(probe, model, point, tally);
    });
    return judged(probe, tally.problems, fmt::format("{} {}", tally.count, counted));
}

bool is_accumulator(SunSpecType type) {
    return type == SunSpecType::Acc16 || type == SunSpecType::Acc32 || type == SunSpecType::Acc64;
}

// A point's sentinel problem beyond the exact match the scan makes: a NaN other than the one
// the specification gives, an EUI-48 of all ones over its reserved register.
std::optional<std::string> wrong_sentinel(const SunSpecPointReading& point) {
    const auto raw = device::sunspec_bits(point.words);
    switch (point.point->type) {
        case SunSpecType::Float32:
            if (std::isnan(std::bit_cast<float>(static_cast<std::uint32_t>(raw))) &&
                raw != 0x7FC00000) {
                return fmt::format("{:08X}, a NaN other than 7FC00000", raw);
            }
            return std::nullopt;
        case SunSpecType::Float64:
            if (std::isnan(std::bit_cast<double>(raw)) && raw != 0x7FF8000000000000) {
                return fmt::format("{:016X}, a NaN other than 7FF8000000000000", raw);
            }
            return std::nullopt;
        case SunSpecType::Eui48:
            if (raw == ~std::uint64_t{0}) {
                return "FFFF FFFF FFFF FFFF: not implemented is 0000 FFFF FFFF FFFF";
            }
            return std::nullopt;
        default:
            return std::nullopt;
    }
}

}  // namespace

std::vector<ProcedureInfo> sunspec_procedures() {
    return {
        modbus_procedure(
            "sunspec_marker",
            "\"SunS\" at 40000, 0 or 50000 (which is reported); a marker one register off "
            "a base fails as such",
            &run_sunspec_marker),
        modbus_procedure("sunspec_common", "the first model is the common model 1, of length 66",
                         &run_sunspec_common),
        modbus_procedure("sunspec_chain_end",
                         "the chain of models ends with the end model 0xFFFF, length 0, inside the "
                         "address space",
                         &run_sunspec_chain_end),
        modbus_procedure(
            "sunspec_lengths",
            "each model's L is what its definition makes it (fixed part plus repeating "
            "groups as their count points say)",
            &run_sunspec_lengths),
        modbus_procedure("sunspec_unknown", "models without a definition are listed",
                         &run_sunspec_unknown),
        modbus_procedure("sunspec_mandatory",
                         "no mandatory point holds its \"not implemented\" value",
                         &run_sunspec_mandatory),
        modbus_procedure("sunspec_sentinels",
                         "float NaNs and EUI-48s not implemented hold their type's exact sentinel",
                         &run_sunspec_sentinels),
        modbus_procedure(
            "sunspec_scale_factors",
            "scale factors within -10..10, implemented where a point they scale is, and "
            "the same when read again",
            &run_sunspec_scale_factors),
        modbus_procedure("sunspec_enums", "enum values are among their symbols",
                         &run_sunspec_enums),
        modbus_procedure("sunspec_strings", "strings are printable ASCII, NUL-padded",
                         &run_sunspec_strings),
        modbus_procedure("sunspec_accumulators", "accumulators read again do not decrease",
                         &run_sunspec_accumulators, {{"interval_ms", 500}}),
        modbus_procedure("sunspec_chunks",
                         "every model read whole in reads of at most 125 registers (the declared "
                         "maximum) that end on point boundaries",
                         &run_sunspec_chunks),
        modbus_procedure(
            "sunspec_rw_points",
            "every implemented RW point takes a different valid value, reads it back, and "
            "is given its first value back",
            &run_sunspec_rw_points, {{"read_back_ms", 1000}}),
        modbus_procedure("sunspec_read_only",
                         "a write to an R point of each model is refused and leaves it unchanged",
                         &run_sunspec_read_only),
        modbus_procedure("sunspec_bad_enum",
                         "a value outside its symbols written to each RW enum point is refused and "
                         "leaves it unchanged",
                         &run_sunspec_bad_enum),
        modbus_procedure(
            "sunspec_line",
            "on a serial line, 1.DA takes a write of its own value, and an RW point takes a "
            "broadcast write (FC 16 to address 0), unanswered",
            &run_sunspec_line, {{"turnaround_ms", 200}}),
    };
}

Outcome run_sunspec_marker(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (!probe.unusable()) return pass(fmt::format("\"SunS\" at {}", probe.scan().base));
    if (probe.models().empty()) return *probe.unusable();
    // A base one register off is the usual slip between 0- and 1-based register numbers.
    for (std::uint32_t base : {39999u, 40001u, 1u, 49999u, 50001u}) {
        const auto words = probe.read(base, 2);
        if (words && (*words)[0] == kMarker[0] && (*words)[1] == kMarker[1]) {
            return probe.fail(fmt::format(
                "\"SunS\" is at {}, one register off the base {}: SunSpec devices put it at "
                "40000, 0 or 50000",
                base, base == 1 ? 0 : (base + 1) / 10000 * 10000));
        }
    }
    return *probe.unusable();
}

Outcome run_sunspec_common(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    const auto& models = probe.scan().models;
    if (models.empty()) return probe.fail("no model follows the marker");
    if (models.front().id != 1) {
        return probe.fail(
            fmt::format("the first model is {}, not the common model 1", models.front().id));
    }
    if (models.front().length != kCommonLength) {
        return probe.fail(
            fmt::format("model 1 has length {}, not {}", models.front().length, kCommonLength));
    }
    return pass(fmt::format("model 1 at {}, length 66", models.front().address));
}

Outcome run_sunspec_chain_end(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    const SunSpecScan& scan = probe.scan();
    if (!scan.chain_problem.empty()) {
        return probe.fail(
            fmt::format("after {} models: {}", scan.models.size(), scan.chain_problem));
    }
    const auto end = probe.read(scan.end_address, 2);
    if (!end) return probe.fail(end.error(), "reading the end model");
    if ((*end)[1] != 0) {
        return probe.fail(
            fmt::format("the end model at {} has length {}, not 0", scan.end_address, (*end)[1]));
    }
    // Every model moves the address on by at least its ID and L, so the chain cannot loop.
    return pass(fmt::format("{} models, the end model 0xFFFF of length 0 at {}", scan.models.size(),
                            scan.end_address));
}

Outcome run_sunspec_lengths(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    std::vector<std::string> problems;
    std::size_t judged_models = 0;
    for (const SunSpecModelReading& model : probe.scan().models) {
        if (model.definition == nullptr) continue;
        ++judged_models;
        if (!model.problem.empty()) {
            problems.push_back(
                fmt::format("model {} at {}: {}", model.id, model.address, model.problem));
        }
    }
    return judged(probe, problems,
                  fmt::format("{} models as long as their definitions make them", judged_models));
}

Outcome run_sunspec_unknown(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    std::string unknown;
    for (const SunSpecModelReading& model : probe.scan().models) {
        if (model.definition != nullptr) continue;
        unknown += fmt::format("{}{} at {}", unknown.empty() ? "" : ", ", model.id, model.address);
    }
    if (unknown.empty()) return pass("every model has a definition");
    return pass("models without a definition (not judged point by point): " + unknown);
}

Outcome run_sunspec_mandatory(Session& session, const Case&) {
    return judge_points(session, "mandatory points implemented",
                        [&](SunSpecProbe&, const SunSpecModelReading& model,
                            const SunSpecPointReading& point, PointTally& tally) {
                            if (!point.point->mandatory || point.point->type == SunSpecType::Pad)
                                return;
                            ++tally.count;
                            if (!point.implemented) {
                                tally.problems.push_back(point_name(model.id, point) +
                                                         " is mandatory, not implemented");
                            }
                        });
}

Outcome run_sunspec_sentinels(Session& session, const Case&) {
    return judge_points(
        session, "points: no float NaN or EUI-48 other than the sentinel",
        [&](SunSpecProbe&, const SunSpecModelReading& model, const SunSpecPointReading& point,
            PointTally& tally) {
            ++tally.count;
            if (auto wrong = wrong_sentinel(point)) {
                tally.problems.push_back(point_name(model.id, point) + " holds " + *wrong);
            }
        });
}

Outcome run_sunspec_scale_factors(Session& session, const Case&) {
    return judge_points(
        session, "scale factors within -10..10 and constant",
        [&](SunSpecProbe& probe, const SunSpecModelReading& model, const SunSpecPointReading& point,
            PointTally& tally) {
            const std::string name = point_name(model.id, point);
            if (point.point->type == SunSpecType::Sunssf) {
                ++tally.count;
                const auto value = static_cast<std::int16_t>(point.words[0]);
                if (point.implemented && (value < kLowestScale || value > kHighestScale)) {
                    tally.problems.push_back(fmt::format("{} = {}, outside -10..10", name, value));
                }
                const auto again = probe.read(point);
                if (!again) {
                    tally.problems.push_back(name + " read again: " + again.error().message);
                } else if (point.point->is_static && *again != point.words) {
                    tally.problems.push_back(fmt::format("{} is static, but read {} then {}", name,
                                                         value,
                                                         static_cast<std::int16_t>((*again)[0])));
                }
            } else if (point.implemented && !point.point->sf.empty() && !point.scale) {
                tally.problems.push_back(name + " is implemented, its scale factor " +
                                         point.point->sf + " is not");
            }
        });
}

Outcome run_sunspec_enums(Session& session, const Case&) {
    return judge_points(
        session, "enum values among their symbols",
        [&](SunSpecProbe&, const SunSpecModelReading& model, const SunSpecPointReading& point,
            PointTally& tally) {
            if (!device::is_sunspec_enum(point.point->type) || point.point->symbols.empty() ||
                !point.implemented) {
                return;
            }
            ++tally.count;
            const auto value = device::sunspec_bits(point.words);
            if (!symbol_name(*point.point, static_cast<double>(value))) {
                tally.problems.push_back(fmt::format("{} = {}, none of its symbols",
                                                     point_name(model.id, point), value));
            }
        });
}

Outcome run_sunspec_strings(Session& session, const Case&) {
    return judge_points(
        session, "strings ASCII and NUL-padded",
        [&](SunSpecProbe&, const SunSpecModelReading& model, const SunSpecPointReading& point,
            PointTally& tally) {
            if (point.point->type != SunSpecType::String) return;
            ++tally.count;
            bool ended = false;
            for (std::size_t i = 0; i < 2 * point.words.size(); ++i) {
                const auto byte = static_cast<std::uint8_t>(point.words[i / 2] >> (i % 2 ? 0 : 8));
                const bool wrong = ended ? byte != 0 : byte != 0 && (byte < 0x20 || byte > 0x7E);
                if (wrong) {
                    tally.problems.push_back(
                        fmt::format("{} byte {} is {:02X}{}", point_name(model.id, point), i, byte,
                                    ended ? " after its NUL" : ", not printable ASCII"));
                    return;
                }
                ended = ended || byte == 0;
            }
        });
}

Outcome run_sunspec_accumulators(Session& session, const Case& c) {
    return judge_points(
        session, "accumulators did not decrease",
        [&](SunSpecProbe& probe, const SunSpecModelReading& model, const SunSpecPointReading& point,
            PointTally& tally) {
            if (!is_accumulator(point.point->type) || !point.implemented) return;
            ++tally.count;
            const auto later = probe.read(point);
            if (!later) {
                tally.problems.push_back(point_name(model.id, point) + ": " +
                                         later.error().message);
            } else if (device::sunspec_accumulator_went_back(point.words, *later)) {
                tally.problems.push_back(
                    fmt::format("{} went from {} down to {}", point_name(model.id, point),
                                device::sunspec_bits(point.words), device::sunspec_bits(*later)));
            }
        },
        std::chrono::milliseconds(param(c, "interval_ms")));
}

Outcome run_sunspec_chunks(Session& session, const Case&) {
    SunSpecProbe probe(session);
    if (probe.unusable()) return *probe.unusable();
    const std::uint32_t most = std::min<std::uint32_t>(session.dut().max_read, 125);
    std::size_t reads = 0;
    for (const SunSpecModelReading& model : probe.scan().models) {
        // Chunks end on point boundaries: the points' ends, then the model's end.
        std::vector<std::uint32_t> ends;
        for (const SunSpecPointReading& point : model.points)
            ends.push_back(point.address + point.point->size);
        ends.push_back(model.address + 2u + model.length);
        std::uint32_t from = model.address;
        std::uint32_t last_end = from;
        for (std::uint32_t end : ends) {
            if (end <= last_end) continue;
            if (end - from > most && last_end > from) {
                ++reads;
                if (auto got = probe.read(from, static_cast<std::uint16_t>(last_end - from));
                    !got) {
                    return probe.fail(got.error(),
                                      fmt::format("model {}: reading {} registers at {}", model.id,
                                                  last_end - from, from));
                }
                from = last_end;
            }
            last_end = end;
        }
        for (; from < last_end; ++reads) {
            const auto count = static_cast<std::uint16_t>(std::min(last_end - from, most));
            if (auto got = probe.read(from, count); !got) {
                return probe.fail(got.error(), fmt::format("model {}: reading {} registers at {}",
                                                           model.id, count, from));
            }
            from += count;
        }
    }
    return pass(fmt::format("{} models read in {} reads of at most {} registers",
                            probe.scan().models.size(), reads, most));
}

}  // namespace mblab::conformance
