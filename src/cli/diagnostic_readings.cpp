#include "cli/diagnostic_readings.hpp"

#include <fmt/core.h>

#include <span>
#include <string>

#include "cli/pdu_text.hpp"
#include "client/hex_text.hpp"

namespace mblab::cli {

namespace {

// [APP] 6.9: what each byte of the comm event log means.
std::string event_text(std::uint8_t event) {
    if (event == 0x00) return "communication restart";
    if (event == 0x04) return "entered listen only mode";
    std::vector<std::string> flags;
    auto flag = [&](unsigned bit, const char* name) {
        if (event & bit) flags.emplace_back(name);
    };
    std::string kind;
    if (event & 0x80) {
        kind = "receive";
        flag(0x02, "communication error");
        flag(0x10, "character overrun");
        flag(0x20, "in listen only mode");
        flag(0x40, "broadcast");
    } else if (event & 0x40) {
        kind = "send";
        flag(0x01, "read exception");
        flag(0x02, "abort exception");
        flag(0x04, "busy exception");
        flag(0x08, "NAK exception");
        flag(0x10, "write timeout");
        flag(0x20, "in listen only mode");
    } else {
        return "reserved";
    }
    std::string text = kind;
    for (std::size_t i = 0; i < flags.size(); ++i)
        text += (i == 0 ? ": " : ", ") + flags[i];
    return text;
}

std::string printable_text(std::span<const std::uint8_t> bytes) {
    std::string text;
    for (auto c : bytes)
        text += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '.';
    return text;
}

Reading field_reading() {
    Reading reading;
    reading.header = {"field", "raw", "value"};
    return reading;
}

void add_field(Reading& reading, const char* name, std::string raw, std::string value,
               nlohmann::json json) {
    reading.rows.push_back({name, std::move(raw), std::move(value)});
    reading.json[name] = std::move(json);
}

void add_status(Reading& reading, std::uint16_t status) {
    add_field(reading, "status", fmt::format("0x{:04X}", status),
              status == 0xFFFF ? "busy"
              : status == 0    ? "ready"
                               : "not a status [APP] defines",
              status);
}

void add_count(Reading& reading, const char* name, std::uint16_t count) {
    add_field(reading, name, fmt::format("0x{:04X}", count), std::to_string(count), count);
}

}  // namespace

Reading exception_status_reading(std::uint8_t status) {
    Reading reading = field_reading();
    std::string outputs;
    for (unsigned bit = 0; bit < 8; ++bit)
        outputs += fmt::format("{}{}", bit ? " " : "", (status >> bit) & 1U);
    add_field(reading, "exception status", fmt::format("0x{:02X}", status),
              "outputs 0..7: " + outputs, status);
    return reading;
}

Reading event_counter_reading(const client::EventCounter& counter) {
    Reading reading = field_reading();
    add_status(reading, counter.status);
    add_count(reading, "event count", counter.event_count);
    return reading;
}

Reading event_log_reading(const client::EventLog& log) {
    Reading reading = field_reading();
    add_status(reading, log.status);
    add_count(reading, "event count", log.event_count);
    add_count(reading, "message count", log.message_count);
    auto& events = reading.json["events"] = nlohmann::json::array();
    for (std::size_t i = 0; i < log.events.size(); ++i) {
        const auto event = log.events[i];
        reading.rows.push_back(
            {fmt::format("event {}", i), fmt::format("0x{:02X}", event), event_text(event)});
        events.push_back({{"byte", event}, {"meaning", event_text(event)}});
    }
    return reading;
}

Reading server_id_reading(const std::vector<std::uint8_t>& data) {
    Reading reading = field_reading();
    add_field(reading, "server id data", client::hex_bytes(data), printable_text(data),
              client::hex_bytes(data));
    reading.notes.push_back(
        "the layout (server id, run indicator 0x00/0xFF, additional data) is device specific");
    return reading;
}

}  // namespace mblab::cli
