#include "web/serve_metrics.hpp"

#include <fmt/format.h>

#include "web/metrics_text.hpp"

namespace mblab::web {

namespace {

std::string hex_code(std::uint8_t function) {
    return fmt::format("0x{:02X}", function);
}

}  // namespace

std::string serve_metrics(const ServeView& view) {
    MetricsText out;
    const auto counts = view.meter.counts();
    struct FunctionCounter {
        const char* name;
        const char* help;
        std::uint64_t RequestCount::*field;
    };
    const FunctionCounter function_counters[] = {
        {"mblab_requests_total", "Modbus requests handed to the device, by unit and function code.",
         &RequestCount::requests},
        {"mblab_exceptions_total",
         "Modbus answers with the exception bit, by unit and function code.",
         &RequestCount::exceptions},
    };
    for (const auto& counter : function_counters) {
        out.family(counter.name, "counter", counter.help);
        for (const auto& row : counts) {
            out.sample(counter.name,
                       {{"unit", std::to_string(row.unit)}, {"function", hex_code(row.function)}},
                       static_cast<double>(row.*counter.field));
        }
    }
    const auto latency = view.meter.latency();
    out.family("mblab_request_duration_seconds", "histogram",
               "Time the server took to answer a request, a fault rule's delay included.");
    out.histogram("mblab_request_duration_seconds", {}, latency.cumulative, latency.count,
                  latency.sum_seconds);
    out.family("mblab_connections", "gauge", "Modbus/TCP connections open.");
    out.sample("mblab_connections", {},
               static_cast<double>(view.connections ? view.connections() : 0));
    struct LineCounter {
        const char* name;
        const char* help;
        std::uint16_t device::CommCounters::*field;
    };
    const LineCounter line_counters[] = {
        {"mblab_line_errors",
         "Serial line errors a unit counted (FC 08 sub 0C: CRC or LRC, parity, short frames); "
         "16 bits, they wrap.",
         &device::CommCounters::bus_errors},
        {"mblab_line_overruns", "Character overruns a unit counted (FC 08 sub 12).",
         &device::CommCounters::overruns},
        {"mblab_bus_messages", "Messages a unit saw on its bus (FC 08 sub 0B).",
         &device::CommCounters::bus_messages},
    };
    std::vector<device::UnitStats> units;
    for (auto unit : view.device.declarations().unit_ids()) {
        if (auto stats = view.device.counters().stats(unit)) units.push_back(*stats);
    }
    for (const auto& counter : line_counters) {
        out.family(counter.name, "gauge", counter.help);
        for (const auto& stats : units) {
            out.sample(counter.name, {{"unit", std::to_string(stats.unit)}},
                       stats.counters.*counter.field);
        }
    }
    return out.text();
}

}  // namespace mblab::web
