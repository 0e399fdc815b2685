#include "device/line_counters.hpp"

namespace mblab::device {

void LineCounters::count_bus_error() {
    units_.locked([](UnitTable& table) {
        for (auto& unit : table.units)
            ++unit.comm().counters.bus_errors;
    });
}

void LineCounters::count_crc_error() {
    count_bus_error();
}

void LineCounters::count_parity_error() {
    count_bus_error();
}

void LineCounters::count_short_frame() {
    count_bus_error();
}

void LineCounters::count_overrun() {
    units_.locked([](UnitTable& table) {
        for (auto& unit : table.units) {
            ++unit.comm().counters.overruns;
            unit.comm().overrun_seen = true;
        }
    });
}

void LineCounters::count_busy_reply(std::uint8_t id) {
    units_.locked([id](UnitTable& table) {
        if (UnitModel* unit = table.find(id)) {
            ++unit->comm().counters.busy;
            ++unit->comm().counters.bus_exceptions;
        }
    });
}

std::optional<UnitStats> LineCounters::stats(std::uint8_t id) const {
    return units_.locked([id](const UnitTable& table) -> std::optional<UnitStats> {
        const UnitModel* unit = table.find(id);
        if (!unit) return std::nullopt;
        const CommState& comm = unit->comm();
        return UnitStats{id, comm.counters, comm.event_count, comm.listen_only};
    });
}

bool LineCounters::clear_counters(std::uint8_t id) {
    return units_.locked([id](UnitTable& table) {
        UnitModel* unit = table.find(id);
        if (!unit) return false;
        unit->comm().counters = {};
        unit->comm().event_count = 0;
        return true;
    });
}

std::optional<std::vector<std::uint8_t>> LineCounters::event_log(std::uint8_t id) const {
    return units_.locked([id](const UnitTable& table) -> std::optional<std::vector<std::uint8_t>> {
        const UnitModel* unit = table.find(id);
        if (!unit) return std::nullopt;
        std::vector<std::uint8_t> out(unit->comm().log.size());
        unit->comm().log.copy(out);
        return out;
    });
}

std::uint8_t LineCounters::ascii_delimiter(std::uint8_t id) const {
    return units_.locked([id](const UnitTable& table) {
        const UnitModel* unit = table.find(id);
        return unit ? unit->comm().ascii_delimiter : static_cast<std::uint8_t>('\n');
    });
}

}  // namespace mblab::device
