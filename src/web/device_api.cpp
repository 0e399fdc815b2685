#include "web/device_api.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <optional>
#include <utility>

#include "device/profile_loader.hpp"
#include "support/name_table.hpp"
#include "web/fault_rule_json.hpp"
#include "web/json_text.hpp"
#include "web/typed_points.hpp"

namespace mblab::web {

namespace {

using device::BankKind;
using nlohmann::json;

// At most this many values in one read or write: a page of the dashboard is far fewer.
constexpr std::uint32_t kMaxValues = 2000;
// Fault rules a unit may have: far more than a test sets up, few enough that a client looping on
// POST cannot grow the process without end.
constexpr std::size_t kMaxRules = 256;
constexpr std::uint32_t kDefaultCount = 10;

// The profile's names for the banks: one table for profiles, state files and the API.
std::string bank_name(BankKind kind) {
    return std::string(device::bank_key(kind));
}

std::optional<BankKind> bank_kind(const std::string& name) {
    for (std::size_t i = 0; i < device::kBankKinds; ++i) {
        const auto kind = static_cast<BankKind>(i);
        if (device::bank_key(kind) == name) return kind;
    }
    return std::nullopt;
}

// A whole decimal number inside [0, high]; nothing else (no sign, no spaces, no suffix).
std::optional<std::uint32_t> whole_number(const std::string& text, std::uint32_t high) {
    std::uint32_t value = 0;
    const auto* end = text.data() + text.size();
    auto [at, ec] = std::from_chars(text.data(), end, value);
    if (text.empty() || ec != std::errc() || at != end || value > high) return std::nullopt;
    return value;
}

std::vector<std::string> split_path(const std::string& path) {
    std::vector<std::string> parts;
    std::size_t at = 0;
    while (at < path.size()) {
        const auto slash = path.find('/', at);
        const auto end = slash == std::string::npos ? path.size() : slash;
        if (end > at) parts.push_back(path.substr(at, end - at));
        at = end + 1;
    }
    return parts;
}

ApiReply ok(const json& body, int status = 200) {
    return {status, json_text(body)};
}

const char* access_name(device::Access access) {
    static constexpr Named<device::Access, const char*> kNames[] = {
        {device::Access::ReadOnly, "ro"},
        {device::Access::WriteOnly, "wo"},
        {device::Access::ReadWrite, "rw"}};
    return name_of(kNames, access, "rw");
}

json comm_json(const device::UnitStats& stats, const std::vector<std::uint8_t>& log) {
    const auto& c = stats.counters;
    return {{"unit", stats.unit},
            {"bus_messages", c.bus_messages},
            {"bus_errors", c.bus_errors},
            {"bus_exceptions", c.bus_exceptions},
            {"server_messages", c.server_messages},
            {"no_response", c.no_response},
            {"naks", c.naks},
            {"busy", c.busy},
            {"overruns", c.overruns},
            {"event_count", stats.event_count},
            {"listen_only", stats.listen_only},
            {"event_log", log}};
}

}  // namespace

ApiReply api_error(int status, const std::string& reason) {
    return {status, json_text({{"error", reason}})};
}

DeviceApi::DeviceApi(ServeView view) : view_(std::move(view)) {
    for (auto unit : view_.device.declarations().unit_ids()) {
        auto& rules = rules_[unit];
        for (auto& spec :
             view_.device.faults().rules(unit).value_or(std::vector<device::FaultSpec>{}))
            rules.push_back({std::move(spec), true});
    }
}

ApiReply DeviceApi::handle(const ApiRequest& request) {
    const auto parts = split_path(request.path);
    const auto& method = request.method;
    const auto not_found = [&] {
        return api_error(404, fmt::format("no such resource: {} {}", method, request.path));
    };
    const auto wrong_method = [&](const char* allowed) {
        return api_error(405, fmt::format("{} takes {}, not {}", request.path, allowed, method));
    };
    if (parts.size() < 2 || parts[0] != "api") return not_found();
    const std::string& top = parts[1];
    if (top == "units" && parts.size() == 2) {
        return method == "GET" ? units() : wrong_method("GET");
    }
    if (top == "counters" && parts.size() == 2) {
        return method == "GET" ? ok(counters()) : wrong_method("GET");
    }
    if (top == "counters" && parts.size() == 3 && parts[2] == "reset") {
        return method == "POST" ? reset_counters() : wrong_method("POST");
    }
    if (top == "traffic" && parts.size() == 2) {
        return method == "GET" ? traffic(request.query) : wrong_method("GET");
    }
    if (top == "state" && parts.size() == 3 && parts[2] == "save") {
        return method == "POST" ? save_state() : wrong_method("POST");
    }
    if (top != "units" || parts.size() < 4) return not_found();

    const auto ids = view_.device.declarations().unit_ids();
    const auto unit = whole_number(parts[2], 255);
    if (!unit || !view_.device.declarations().of(static_cast<std::uint8_t>(*unit))) {
        return api_error(
            404, fmt::format("unit {}: no such unit (units: {})", parts[2], fmt::join(ids, ",")));
    }
    const auto id = static_cast<std::uint8_t>(*unit);
    if (parts[3] == "faults") return change_rules(request, id, parts);
    const auto kind = bank_kind(parts[3]);
    if (!kind) {
        return api_error(404, fmt::format("{}: no such bank (coils, discrete_inputs, "
                                          "holding_registers, input_registers, faults)",
                                          parts[3]));
    }
    if (parts.size() == 4) {
        return method == "GET" ? read_values(id, *kind, request.query) : wrong_method("GET");
    }
    if (parts.size() == 5) {
        return method == "PUT" ? write_values(id, *kind, parts[4], request.body)
                               : wrong_method("PUT");
    }
    return not_found();
}

ApiReply DeviceApi::units() const {
    json out = json::array();
    for (const auto& spec : view_.device.declarations().profile().units) {
        json banks = json::object();
        for (std::size_t i = 0; i < device::kBankKinds; ++i) {
            const auto kind = static_cast<BankKind>(i);
            const std::string name = bank_name(kind);
            json ranges = json::array();
            for (const auto& range : spec.banks[static_cast<std::size_t>(kind)]) {
                ranges.push_back({{"start", range.start},
                                  {"count", range.count},
                                  {"access", access_name(range.access)},
                                  {"name", range.name}});
            }
            banks[name] = ranges;
        }
        out.push_back({{"unit", spec.id},
                       {"name", spec.name},
                       {"banks", banks},
                       {"start_bank", start_bank(spec)}});
    }
    return ok(out);
}

ApiReply DeviceApi::read_values(std::uint8_t unit, BankKind kind,
                                const std::map<std::string, std::string>& query) const {
    std::uint32_t start = 0;
    std::uint32_t count = kDefaultCount;
    if (auto it = query.find("start"); it != query.end()) {
        const auto value = whole_number(it->second, 65535);
        if (!value) return api_error(400, "start: expected an address from 0 to 65535");
        start = *value;
    }
    if (auto it = query.find("count"); it != query.end()) {
        const auto value = whole_number(it->second, kMaxValues);
        if (!value || *value == 0) {
            return api_error(400, fmt::format("count: expected 1 to {}", kMaxValues));
        }
        count = *value;
    }
    if (start + count > 65536) {
        return api_error(400,
                         fmt::format("start {} + count {} runs past address 65535", start, count));
    }
    const auto values = view_.device.data().values(unit, kind, start, count);
    json list = json::array();
    for (const auto& value : values.value_or(std::vector<std::optional<std::uint16_t>>{})) {
        if (value) {
            list.push_back(*value);
        } else {
            list.push_back(nullptr);
        }
    }
    return ok({{"unit", unit}, {"bank", bank_name(kind)}, {"start", start}, {"values", list}});
}

ApiReply DeviceApi::write_values(std::uint8_t unit, BankKind kind, const std::string& address,
                                 const std::string& body) {
    const auto start = whole_number(address, 65535);
    if (!start)
        return api_error(400, fmt::format("{}: expected an address from 0 to 65535", address));
    std::string error;
    const auto body_json = parse_json_body(body, error);
    if (!body_json) return api_error(400, error);
    const json& parsed = *body_json;
    if (!parsed.is_object() || !parsed.contains("values") || !parsed["values"].is_array() ||
        parsed["values"].empty() || parsed["values"].size() > kMaxValues) {
        return api_error(
            400, fmt::format("expected {{\"values\": [...]}} with 1 to {} values", kMaxValues));
    }
    const std::int64_t high = device::is_bit_bank(kind) ? 1 : 65535;
    std::vector<std::uint16_t> values;
    for (const json& value : parsed["values"]) {
        if (!value.is_number_integer() || value.get<std::int64_t>() < 0 ||
            value.get<std::int64_t>() > high) {
            return api_error(
                400, fmt::format("values: {} takes integers from 0 to {}", bank_name(kind), high));
        }
        values.push_back(value.get<std::uint16_t>());
    }
    if (*start + values.size() > 65536) {
        return api_error(
            400, fmt::format("{} values from {} run past address 65535", values.size(), *start));
    }
    const auto written = view_.write_values ? view_.write_values(unit, kind, *start, values)
                         : view_.device.data().set_values(unit, kind, *start, values)
                             ? ValueWrite::Written
                             : ValueWrite::Unmapped;
    if (written == ValueWrite::Unmapped) {
        return api_error(409, fmt::format("unit {} {} {}..{}: not every address is mapped", unit,
                                          bank_name(kind), *start, *start + values.size() - 1));
    }
    if (written == ValueWrite::NotDurable) {
        return api_error(500,
                         "the values were written but could not be made durable (the "
                         "journal could not be written): do not take them as kept");
    }
    return ok(
        {{"unit", unit}, {"bank", bank_name(kind)}, {"start", *start}, {"written", values.size()}});
}

ApiReply DeviceApi::list_rules(std::uint8_t unit) {
    json out = json::array();
    const auto& rules = rules_[unit];
    for (std::size_t i = 0; i < rules.size(); ++i) {
        auto rule = fault_rule_json(rules[i].spec);
        rule["index"] = i;
        rule["enabled"] = rules[i].enabled;
        out.push_back(rule);
    }
    return ok(out);
}

ApiReply DeviceApi::change_rules(const ApiRequest& request, std::uint8_t unit,
                                 const std::vector<std::string>& parts) {
    std::lock_guard lock(rules_mutex_);
    auto& rules = rules_[unit];
    std::optional<std::size_t> index;
    if (parts.size() == 5) {
        const auto number = whole_number(parts[4], 1'000'000);
        if (!number || *number >= rules.size()) {
            return api_error(404, fmt::format("fault rule {}: unit {} has {} rules (0..)", parts[4],
                                              unit, rules.size()));
        }
        index = *number;
    } else if (parts.size() > 5) {
        return api_error(404, fmt::format("no such resource: {} {}", request.method, request.path));
    }
    if (request.method == "GET")
        return index ? api_error(405, "GET takes the list") : list_rules(unit);
    if (request.method == "DELETE" && index) {
        rules.erase(rules.begin() + static_cast<std::ptrdiff_t>(*index));
        apply_rules(unit);
        return list_rules(unit);
    }
    if ((request.method == "POST" && !index) || (request.method == "PUT" && index)) {
        std::string error;
        const auto body_json = parse_json_body(request.body, error);
        if (!body_json) return api_error(400, error);
        const json& parsed = *body_json;
        Rule rule;
        if (!parse_fault_rule(parsed, rule.spec, error)) return api_error(400, error);
        if (parsed.contains("enabled")) {
            if (!parsed["enabled"].is_boolean())
                return api_error(400, "enabled: expected true or false");
            rule.enabled = parsed["enabled"].get<bool>();
        }
        if (index) {
            rules[*index] = std::move(rule);
        } else if (rules.size() >= kMaxRules) {
            return api_error(
                409, fmt::format("unit {} has {} fault rules, the most it takes", unit, kMaxRules));
        } else {
            rules.push_back(std::move(rule));
        }
        apply_rules(unit);
        auto reply = list_rules(unit);
        reply.status = index ? 200 : 201;
        return reply;
    }
    return api_error(405,
                     index ? "a fault rule takes PUT or DELETE" : "the rules take GET or POST");
}

void DeviceApi::apply_rules(std::uint8_t unit) {
    std::vector<device::FaultSpec> enabled;
    for (const auto& rule : rules_[unit]) {
        if (rule.enabled) enabled.push_back(rule.spec);
    }
    view_.device.faults().set_rules(unit, std::move(enabled));
}

json DeviceApi::counters() const {
    json requests = json::array();
    for (const auto& row : view_.meter.counts()) {
        requests.push_back({{"unit", row.unit},
                            {"function", row.function},
                            {"requests", row.requests},
                            {"exceptions", row.exceptions}});
    }
    const auto latency = view_.meter.latency();
    json units = json::array();
    for (auto unit : view_.device.declarations().unit_ids()) {
        const auto stats = view_.device.counters().stats(unit);
        const auto log = view_.device.counters().event_log(unit);
        if (stats && log) units.push_back(comm_json(*stats, *log));
    }
    return {{"requests", requests},
            {"latency", {{"count", latency.count}, {"sum_seconds", latency.sum_seconds}}},
            {"connections", view_.connections ? view_.connections() : 0},
            {"units", units}};
}

ApiReply DeviceApi::reset_counters() {
    view_.meter.reset();
    for (auto unit : view_.device.declarations().unit_ids())
        view_.device.counters().clear_counters(unit);
    return ok(counters());
}

ApiReply DeviceApi::save_state() {
    if (!view_.save_state)
        return api_error(409, "serve runs without --state FILE: nothing to save to");
    std::string file_or_error;
    if (!view_.save_state(file_or_error)) return api_error(500, file_or_error);
    return ok({{"saved", file_or_error}});
}

ApiReply DeviceApi::traffic(const std::map<std::string, std::string>& query) const {
    if (!view_.traffic) return api_error(404, "this server keeps no traffic log");
    std::uint64_t after = 0;
    if (const auto it = query.find("after"); it != query.end()) {
        const auto& text = it->second;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), after);
        if (ec != std::errc() || end != text.data() + text.size()) {
            return api_error(400, fmt::format("after={}: expected a whole number", text));
        }
    }
    std::uint64_t last = 0;
    json entries = json::array();
    for (const auto& entry : view_.traffic->recent(after, last))
        entries.push_back(server::traffic_json(entry));
    return ok(json{{"last", last}, {"entries", std::move(entries)}});
}

json DeviceApi::live_event(const std::map<std::string, std::string>& page) {
    json event{{"counters", counters()}};
    const auto unit = page.find("unit");
    const auto bank = page.find("bank");
    if (unit != page.end() && bank != page.end()) {
        auto reply = handle({"GET", "/api/units/" + unit->second + "/" + bank->second, page, ""});
        auto shown = json::parse(reply.body, nullptr, false);
        // The page's typed points, decoded as the profile lays them out (none: left out).
        if (reply.status == 200 && shown.contains("values")) {
            auto points = page_points(view_.device, shown["unit"].get<std::uint8_t>(),
                                      *bank_kind(bank->second), shown["start"].get<std::uint32_t>(),
                                      static_cast<std::uint32_t>(shown["values"].size()));
            if (!points.empty()) shown["points"] = std::move(points);
        }
        event["page"] = std::move(shown);
    }
    return event;
}

}  // namespace mblab::web
