#include "conformance/sunspec_scan.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace mblab::conformance {
namespace {

using device::SunSpecGroup;
using device::SunSpecModel;
using device::SunSpecPoint;
using device::SunSpecType;

constexpr std::uint16_t kMarkerHigh = 0x5375;  // "Su"
constexpr std::uint16_t kMarkerLow = 0x6E53;   // "nS"
constexpr std::uint16_t kEndModel = 0xFFFF;

protocol::Result<std::vector<std::uint16_t>, std::string> read_block(const RegisterReader& read,
                                                                     std::uint32_t address,
                                                                     std::uint32_t count) {
    std::vector<std::uint16_t> words;
    words.reserve(count);
    while (count > 0) {
        const auto chunk =
            static_cast<std::uint16_t>(std::min<std::uint32_t>(count, kMaxRegistersPerRead));
        auto answer = read(static_cast<std::uint16_t>(address), chunk);
        if (!answer) {
            return "reading " + std::to_string(chunk) + " registers at " + std::to_string(address) +
                   ": " + answer.error().message;
        }
        words.insert(words.end(), answer->begin(), answer->end());
        address += chunk;
        count -= chunk;
    }
    return words;
}

// Decodes one model's registers (ID first) by its definition.
class ModelDecoder {
  public:
    ModelDecoder(const std::vector<std::uint16_t>& words, std::uint32_t address,
                 SunSpecModelReading& reading)
        : words_(words), address_(address), reading_(reading) {}

    void decode(const SunSpecModel& model) {
        const std::uint32_t end = instance(model.group, 0, "", {}, {});
        if (end != words_.size() && reading_.problem.empty()) {
            reading_.problem = "L is " + std::to_string(reading_.length) +
                               ", the definition makes " + std::to_string(end - 2);
        }
    }

  private:
    // The points of one instance at `start`, then its groups; where the instance ends. Counts and
    // scale factors named by a group are its own points' or those of the instances above it.
    std::uint32_t instance(const SunSpecGroup& group, std::uint32_t start, const std::string& where,
                           std::map<std::string, int> scales,
                           std::map<std::string, std::uint32_t> counts) {
        for (const SunSpecPoint& point : group.points) {
            const std::uint32_t at = start + point.offset;
            if (at + point.size > words_.size()) {
                note("the model ends inside point " + point.name);
                return static_cast<std::uint32_t>(words_.size());
            }
            const std::uint16_t first = words_[at];
            if (point.type == SunSpecType::Sunssf && first != 0x8000) {
                scales[point.name] = static_cast<std::int16_t>(first);
            }
            if (point.size == 1) counts[point.name] = first;
        }
        std::uint32_t at = start;
        for (const SunSpecPoint& point : group.points) {
            const std::uint32_t offset = start + point.offset;
            SunSpecPointReading reading;
            reading.point = &point;
            reading.group = where;
            reading.address = address_ + offset;
            reading.words.assign(words_.begin() + offset, words_.begin() + offset + point.size);
            reading.implemented = !device::is_not_implemented(point, reading.words);
            if (reading.implemented) scale(point, scales, reading);
            reading_.points.push_back(std::move(reading));
            at = offset + point.size;
        }
        const auto size = static_cast<std::uint32_t>(words_.size());
        for (const SunSpecGroup& child : group.groups) {
            std::uint32_t times = child.fixed_count;
            if (!child.count_point.empty()) {
                const auto found = counts.find(child.count_point);
                times = found == counts.end() ? 0 : found->second;
            } else if (child.fixed_count == 0 && child.size > 0) {
                times = (size - at) / child.size;
            }
            for (std::uint32_t i = 0; i < times && at < size; ++i) {
                const std::string name = (where.empty() ? "" : where + ".") + child.name + "[" +
                                         std::to_string(i + 1) + "]";
                at = instance(child, at, name, scales, counts);
            }
        }
        return at;
    }

    void scale(const SunSpecPoint& point, const std::map<std::string, int>& scales,
               SunSpecPointReading& reading) {
        const auto raw = device::sunspec_raw_value(point.type, reading.words);
        if (!raw) return;
        if (point.fixed_sf) {
            reading.scale = point.fixed_sf;
        } else if (!point.sf.empty()) {
            const auto found = scales.find(point.sf);
            if (found == scales.end()) return;
            reading.scale = found->second;
        }
        // Dividing by 10^n for a negative scale factor keeps 2301 * 10^-1 exactly 230.1.
        const int sf = reading.scale.value_or(0);
        reading.value = sf < 0 ? *raw / std::pow(10.0, -sf) : *raw * std::pow(10.0, sf);
    }

    void note(const std::string& problem) {
        if (reading_.problem.empty()) reading_.problem = problem;
    }

    const std::vector<std::uint16_t>& words_;
    std::uint32_t address_;
    SunSpecModelReading& reading_;
};

protocol::Result<std::uint16_t, std::string> find_marker(const RegisterReader& read) {
    std::string tried;
    for (std::uint16_t base : kSunSpecBases) {
        auto answer = read(base, 2);
        if (answer && answer->size() == 2 && (*answer)[0] == kMarkerHigh &&
            (*answer)[1] == kMarkerLow) {
            return base;
        }
        if (!answer && answer.error().kind != client::ErrorKind::Exception) {
            return "reading the marker at " + std::to_string(base) + ": " + answer.error().message;
        }
        tried += (tried.empty() ? "" : ", ") + std::to_string(base);
    }
    return "no SunSpec marker (\"SunS\", 0x5375 0x6E53) at " + tried;
}

}  // namespace

protocol::Result<SunSpecScan, std::string> scan_sunspec(
    const RegisterReader& read, const std::map<std::uint16_t, SunSpecModel>& models) {
    const auto base = find_marker(read);
    if (!base) return base.error();
    SunSpecScan scan;
    scan.base = *base;
    // Each model takes at least its ID and L, so addresses only grow: the chain cannot loop
    // without leaving the address space, which ends the scan.
    std::uint32_t address = *base + 2U;
    while (true) {
        if (address + 2 > 0x10000) {
            scan.chain_problem =
                "the chain runs past the last register (65535) without the end model 0xFFFF";
            return scan;
        }
        const auto header = read_block(read, address, 2);
        if (!header) {
            scan.chain_problem = header.error();
            return scan;
        }
        if ((*header)[0] == kEndModel) {
            scan.end_address = address;
            return scan;
        }
        SunSpecModelReading reading;
        reading.id = (*header)[0];
        reading.length = (*header)[1];
        reading.address = address;
        if (address + 2U + reading.length > 0x10000) {
            scan.chain_problem = "model " + std::to_string(reading.id) + " at " +
                                 std::to_string(address) + " has length " +
                                 std::to_string(reading.length) +
                                 ", past the last register (65535)";
            return scan;
        }
        const auto found = models.find(reading.id);
        if (found != models.end()) {
            reading.definition = &found->second;
            const auto words = read_block(read, address, reading.length + 2U);
            if (!words) {
                scan.chain_problem = words.error();
                return scan;
            }
            ModelDecoder(*words, address, reading).decode(found->second);
        } else {
            reading.problem = "no definition of model " + std::to_string(reading.id);
        }
        scan.models.push_back(std::move(reading));
        address += 2U + scan.models.back().length;
    }
}

std::optional<std::string> symbol_name(const device::SunSpecPoint& point, double value) {
    for (const device::SunSpecSymbol& symbol : point.symbols) {
        if (static_cast<double>(symbol.value) == value) return symbol.name;
    }
    return std::nullopt;
}

}  // namespace mblab::conformance
