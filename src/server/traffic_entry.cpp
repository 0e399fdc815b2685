#include "server/traffic_entry.hpp"

#include <time.h>

#include <concepts>
#include <cstdio>
#include <variant>

#include "protocol/function_code.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"
#include "support/json_document.hpp"

namespace mblab::server {

namespace {

using namespace protocol;

template <class View>
void take_values(TrafficFields& fields, const View& view) {
    fields.values.clear();
    for (std::size_t i = 0; i < view.size() && i < kShortValues; ++i)
        fields.values.push_back(static_cast<std::uint16_t>(view[i]));
    fields.more_values = view.size() > kShortValues;
}

// The fields are found by their names in the protocol's message types, so a new message type
// that has an address or values shows them without a change here.
struct RequestPicker {
    TrafficFields& fields;

    template <class M>
    void operator()(const M& m) const {
        if constexpr (requires { m.address; }) fields.address = m.address;
        if constexpr (requires { m.quantity; }) fields.quantity = m.quantity;
        if constexpr (requires { m.read_address; }) {
            // FC 17 shows its read range; its written values follow as for any write.
            fields.address = m.read_address;
            fields.quantity = m.read_quantity;
        }
        if constexpr (requires { m.value; }) fields.values = {m.value};
        if constexpr (requires { m.values.size(); }) take_values(fields, m.values);
        if constexpr (requires { m.sub_function; }) fields.sub_function = m.sub_function;
    }
};

// A read's values come back in its answer; a write's answer only echoes the request.
struct ResponsePicker {
    TrafficFields& fields;

    template <class M>
    void operator()(const M& m) const {
        if constexpr (std::same_as<M, ExceptionResponse>) {
            fields.exception = m.code;
        } else if constexpr (std::same_as<M, ReadBitsResponse>) {
            const std::size_t count = fields.quantity.value_or(0);
            take_values(fields, BitView(m.packed, std::min(count, m.packed.size() * 8)));
        } else if constexpr (requires { m.values.size(); }) {
            take_values(fields, m.values);
        }
    }
};

std::string two_hex(unsigned value) {
    char text[8];
    std::snprintf(text, sizeof text, "%02X", value & 0xFFU);
    return text;
}

std::string utc_time(std::chrono::system_clock::time_point time) {
    const auto seconds = std::chrono::floor<std::chrono::seconds>(time);
    const auto millis =
        std::chrono::duration_cast<std::chrono::milliseconds>(time - seconds).count();
    const std::time_t t = std::chrono::system_clock::to_time_t(seconds);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[64];
    std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900,
                  tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec,
                  static_cast<int>(millis));
    return text;
}

const char* answer_kind(const TrafficEntry& entry, const TrafficFields& fields) {
    switch (entry.action) {
        case device::ReplyAction::NoAnswer:
            return "none";
        case device::ReplyAction::Close:
            return "close";
        case device::ReplyAction::Answer:
            break;
    }
    return fields.exception ? "exception" : "values";
}

}  // namespace

TrafficFields traffic_fields(const TrafficEntry& entry) {
    TrafficFields fields;
    if (entry.request.empty()) {
        fields.undecoded = "empty PDU";
        return fields;
    }
    fields.function = entry.request.front();
    fields.name = function_name(fields.function);
    const auto request = decode_request(entry.request);
    if (request) {
        std::visit(RequestPicker{fields}, *request);
    } else {
        fields.undecoded = std::string(request.error().field) + ": " + request.error().reason;
    }
    if (entry.action != device::ReplyAction::Answer || entry.response.empty()) return fields;
    if (const auto response = decode_response(entry.response)) {
        std::visit(ResponsePicker{fields}, *response);
    } else if ((entry.response.front() & kExceptionBit) && entry.response.size() >= 2) {
        fields.exception = static_cast<ExceptionCode>(entry.response[1]);
    }
    return fields;
}

std::string traffic_text(const TrafficEntry& entry) {
    const auto fields = traffic_fields(entry);
    std::string line = utc_time(entry.time) + ' ' + (entry.peer.empty() ? "-" : entry.peer) +
                       " unit " + std::to_string(entry.unit) + " 0x" + two_hex(fields.function) +
                       ' ' + std::string(fields.name);
    if (fields.sub_function) {
        line += " sub-function " + std::to_string(*fields.sub_function) + " (" +
                std::string(diagnostic_sub_name(*fields.sub_function)) + ')';
    }
    if (fields.address) line += " address " + std::to_string(*fields.address);
    if (fields.quantity) line += " quantity " + std::to_string(*fields.quantity);
    if (!fields.undecoded.empty()) line += " (does not decode: " + fields.undecoded + ')';
    line += " ->";
    const std::string kind = answer_kind(entry, fields);
    if (kind == "exception") {
        line += " exception " + two_hex(static_cast<unsigned>(*fields.exception)) + " (" +
                std::string(exception_name(*fields.exception)) + ')';
    } else if (kind == "none") {
        line += " no answer";
    } else if (kind == "close") {
        line += " connection closed";
    } else if (fields.values.empty()) {
        line += " ok";
    } else {
        line += " values";
        for (const auto value : fields.values)
            line += ' ' + std::to_string(value);
        if (fields.more_values) line += " ...";
    }
    line += " (" + std::to_string(entry.latency.count()) + " us)";
    return line;
}

nlohmann::json traffic_json(const TrafficEntry& entry) {
    const auto fields = traffic_fields(entry);
    nlohmann::json out = {
        {"time", utc_time(entry.time)},
        {"peer", entry.peer},
        {"unit", entry.unit},
        {"function", fields.function},
        {"name", std::string(fields.name)},
    };
    if (fields.sub_function) out["sub_function"] = *fields.sub_function;
    if (fields.address) out["address"] = *fields.address;
    if (fields.quantity) out["quantity"] = *fields.quantity;
    if (!fields.undecoded.empty()) out["undecoded"] = fields.undecoded;
    if (!fields.values.empty()) {
        out["values"] = fields.values;
        out["more_values"] = fields.more_values;
    }
    out["answer"] = answer_kind(entry, fields);
    if (fields.exception) {
        out["exception"] = {{"code", static_cast<unsigned>(*fields.exception)},
                            {"name", std::string(exception_name(*fields.exception))}};
    }
    out["latency_us"] = entry.latency.count();
    return out;
}

std::string traffic_ndjson(const TrafficEntry& entry) {
    // A peer's text comes from the system and the names from tables: all ASCII, but a bad byte
    // must not throw on the Modbus thread.
    return json_document(traffic_json(entry), -1);
}

}  // namespace mblab::server
