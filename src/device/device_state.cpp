#include "device/device_state.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "device/profile_loader.hpp"
#include "protocol/function_table.hpp"
#include "protocol/limits.hpp"
#include "protocol/request.hpp"

namespace mblab::device {

namespace {

using nlohmann::json;

constexpr std::string_view kFormat = "mblab-device-state";
constexpr int kVersion = 1;
constexpr std::array<BankKind, 2> kWritableBanks = {BankKind::Coils, BankKind::HoldingRegisters};

bool writable(Access access) {
    return access != Access::ReadOnly;
}

// One change load() will make once the whole text has been checked.
struct Assignment {
    UnitModel* unit = nullptr;
    BankKind kind = BankKind::Coils;
    std::uint32_t start = 0;
    std::size_t file = 0;  // index in the unit's files when is_file
    bool is_file = false;
    std::vector<std::uint16_t> values;
};

// Reads an array of 16-bit values (or bits) of exactly `size` elements.
bool read_values(const json& node, std::size_t size, std::uint16_t max, const std::string& path,
                 std::vector<std::uint16_t>& out, std::string& error) {
    if (!node.is_array() || node.size() != size) {
        error = path + ": expected an array of " + std::to_string(size) + " values";
        return false;
    }
    out.clear();
    out.reserve(size);
    for (const auto& element : node) {
        if (!element.is_number_unsigned() || element.get<std::uint64_t>() > max) {
            error = path + ": values must be integers from 0 to " + std::to_string(max);
            return false;
        }
        out.push_back(static_cast<std::uint16_t>(element.get<std::uint64_t>()));
    }
    return true;
}

}  // namespace

StateSnapshot DeviceState::snapshot() const {
    return units_.locked([this](const UnitTable& table) { return copy_of(table); });
}

StateSnapshot DeviceState::copy_of(const UnitTable& table) const {
    StateSnapshot snapshot;
    snapshot.profile = units_.profile().name;
    for (const auto& unit : table.units) {
        StateSnapshot::Unit& copy = snapshot.units.emplace_back();
        copy.id = unit.spec().id;
        for (BankKind kind : kWritableBanks) {
            const DataBank& bank = unit.bank(kind);
            for (const auto& segment : bank.segments()) {
                if (!writable(segment.access)) continue;
                StateSnapshot::Range& range = copy.ranges.emplace_back();
                range.kind = kind;
                range.start = segment.start;
                range.values.resize(segment.end - segment.start);
                for (std::uint32_t i = 0; i < segment.end - segment.start; ++i)
                    range.values[i] = bank.at(segment.index + i);
            }
        }
        copy.files = unit.files().files();
    }
    return snapshot;
}

std::string StateSnapshot::to_json() const {
    json root;
    root["format"] = kFormat;
    root["version"] = kVersion;
    root["profile"] = profile;
    json out_units = json::array();
    for (const auto& unit : units) {
        json entry;
        entry["id"] = unit.id;
        for (BankKind kind : kWritableBanks) {
            json ranges = json::array();
            for (const auto& range : unit.ranges) {
                if (range.kind != kind) continue;
                ranges.push_back({{"start", range.start}, {"values", range.values}});
            }
            entry[std::string(bank_key(kind))] = std::move(ranges);
        }
        json files = json::array();
        for (const auto& file : unit.files) {
            files.push_back({{"number", file.number}, {"records", file.records}});
        }
        entry["files"] = std::move(files);
        out_units.push_back(std::move(entry));
    }
    root["units"] = std::move(out_units);
    return root.dump(1) + "\n";
}

std::string DeviceState::save() const {
    return snapshot().to_json();
}

std::uint64_t DeviceState::writes() const {
    return units_.locked([](const UnitTable& table) { return table.state_writes; });
}

bool DeviceState::replay_write(const RequestContext& context,
                               std::span<const std::uint8_t> request) {
    if (request.empty()) return false;
    const protocol::FunctionRow* row = protocol::find_function(request[0]);
    if (!row || row->writes != protocol::Writes::Yes) return false;
    const auto decoded = protocol::decode_request(request);
    if (!decoded) return false;
    std::array<std::uint8_t, protocol::limits::kMaxPdu> scratch{};
    return units_.locked([&](UnitTable& table) {
        const Route target = table.route(context);
        auto run = [&](UnitModel& unit) {
            const auto outcome = unit.serve(decoded.value(), scratch);
            return outcome && !std::holds_alternative<protocol::ExceptionResponse>(*outcome);
        };
        if (target.kind == RouteKind::Unit) return run(*target.unit);
        if (target.kind != RouteKind::Broadcast) return false;
        for (auto& unit : table.units)
            run(unit);
        return true;
    });
}

bool DeviceState::load(std::string_view text, std::string& error) {
    return units_.locked([&](UnitTable& table) { return load_into(table, text, error); });
}

bool DeviceState::load_into(UnitTable& table, std::string_view text, std::string& error) {
    const json root = json::parse(text, nullptr, false);
    if (root.is_discarded()) {
        error = "the state is not valid JSON";
        return false;
    }
    if (!root.is_object()) {
        error = std::string(
                    "expected a JSON object (a file written by mblab serve --state), "
                    "found ") +
                root.type_name();
        return false;
    }
    // Checked by type first: json::value() throws when the key holds another type.
    const bool format_ok = root.contains("format") && root["format"] == kFormat;
    const bool version_ok = root.contains("version") && root["version"].is_number_integer() &&
                            root["version"] == kVersion;
    if (!format_ok || !version_ok) {
        error = "format: expected \"" + std::string(kFormat) + "\" version " +
                std::to_string(kVersion) + " (a file written by mblab serve --state)";
        return false;
    }
    const json* units = root.contains("units") ? &root["units"] : nullptr;
    if (!units || !units->is_array()) {
        error = "units: expected an array";
        return false;
    }
    std::vector<Assignment> plan;
    for (std::size_t u = 0; u < units->size(); ++u) {
        const json& entry = (*units)[u];
        const std::string path = "units[" + std::to_string(u) + "]";
        if (!entry.is_object() || !entry.contains("id") || !entry["id"].is_number_unsigned() ||
            entry["id"].get<std::uint64_t>() > 255) {
            error = path + ".id: expected a unit id";
            return false;
        }
        UnitModel* unit = table.find(static_cast<std::uint8_t>(entry["id"].get<std::uint64_t>()));
        if (!unit) {
            error = path + ".id: the profile has no unit " + entry["id"].dump();
            return false;
        }
        for (BankKind kind : kWritableBanks) {
            const std::string key(bank_key(kind));
            if (!entry.contains(key)) continue;
            const json& ranges = entry[key];
            if (!ranges.is_array()) {
                error = path + "." + key + ": expected an array of ranges";
                return false;
            }
            const std::uint16_t max = is_bit_bank(kind) ? 1 : 0xFFFF;
            for (std::size_t r = 0; r < ranges.size(); ++r) {
                const std::string rpath = path + "." + key + "[" + std::to_string(r) + "]";
                const json& range = ranges[r];
                const auto& segments = unit->bank(kind).segments();
                const auto segment =
                    std::find_if(segments.begin(), segments.end(), [&](const auto& s) {
                        return writable(s.access) && range.is_object() && range.contains("start") &&
                               range["start"] == s.start;
                    });
                if (segment == segments.end()) {
                    error = rpath + ".start: no writable range of the profile starts there";
                    return false;
                }
                Assignment change{unit, kind, segment->start, 0, false, {}};
                if (!read_values(range.contains("values") ? range["values"] : json(),
                                 segment->end - segment->start, max, rpath + ".values",
                                 change.values, error)) {
                    return false;
                }
                plan.push_back(std::move(change));
            }
        }
        if (!entry.contains("files")) continue;
        if (!entry["files"].is_array()) {
            error = path + ".files: expected an array of files";
            return false;
        }
        const auto& files = unit->files().files();
        for (std::size_t f = 0; f < entry["files"].size(); ++f) {
            const json& file = entry["files"][f];
            const std::string fpath = path + ".files[" + std::to_string(f) + "]";
            const auto match = std::find_if(files.begin(), files.end(), [&](const FileSpec& s) {
                return file.is_object() && file.contains("number") && file["number"] == s.number;
            });
            if (match == files.end()) {
                error = fpath + ".number: the profile has no such file";
                return false;
            }
            Assignment change{unit, BankKind::HoldingRegisters,
                              0,    static_cast<std::size_t>(match - files.begin()),
                              true, {}};
            if (!read_values(file.contains("records") ? file["records"] : json(),
                             match->records.size(), 0xFFFF, fpath + ".records", change.values,
                             error)) {
                return false;
            }
            plan.push_back(std::move(change));
        }
    }
    for (auto& change : plan) {
        if (change.is_file) {
            change.unit->files().files()[change.file].records = std::move(change.values);
        } else {
            change.unit->bank(change.kind).write(change.start, change.values, std::nullopt);
        }
    }
    return true;
}

}  // namespace mblab::device
