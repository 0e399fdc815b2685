#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "device/request_handler.hpp"
#include "protocol/exception_code.hpp"

// One request and its answer as `mblab serve --log` and the dashboard show them. The PDUs are
// decoded by the protocol layer (decode_request, decode_response, function_name); this file only
// picks the fields a traffic line shows: where, how many, and the values when they are few.
namespace mblab::server {

struct TrafficEntry {
    std::chrono::system_clock::time_point time{};
    std::string peer = {};  // "192.0.2.7:50312", or the line's name
    std::uint8_t unit = 0;
    std::vector<std::uint8_t> request = {};  // the request PDU
    device::ReplyAction action = device::ReplyAction::Answer;
    std::vector<std::uint8_t> response = {};  // the response PDU, when answered
    std::chrono::microseconds latency{0};
};

// Values a line shows at most; a longer read or write shows these and says there are more.
inline constexpr std::size_t kShortValues = 8;

struct TrafficFields {
    std::uint8_t function = 0;
    std::string_view name;  // protocol::function_name()
    std::optional<std::uint16_t> sub_function;
    std::optional<std::uint16_t> address;
    std::optional<std::uint16_t> quantity;
    std::vector<std::uint16_t> values;  // written, or read back; at most kShortValues
    bool more_values = false;
    std::optional<protocol::ExceptionCode> exception;
    std::string undecoded;  // why the request did not decode, when it did not
};

TrafficFields traffic_fields(const TrafficEntry& entry);

// "2026-11-27T10:15:02.123Z 127.0.0.1:50312 unit 1 0x03 read holding registers address 0
// quantity 2 -> values 1 2 (41 us)", without a newline.
std::string traffic_text(const TrafficEntry& entry);
// The same as a JSON object: time, peer, unit, function, name, sub_function, address, quantity,
// values, more_values, answer ("values"/"exception"/"none"/"close"), exception {code, name},
// latency_us. Absent fields are left out.
nlohmann::json traffic_json(const TrafficEntry& entry);
// traffic_json() on one line, without a newline (NDJSON).
std::string traffic_ndjson(const TrafficEntry& entry);

}  // namespace mblab::server
