#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "device/reference_device.hpp"
#include "server/traffic_log.hpp"
#include "web/request_meter.hpp"

// The REST API of `mblab serve --http` as requests in, replies out, without a socket
// (docs/http.md, docs/http-api.yaml). The HTTP server (http_server.hpp) only carries them.
// Called from the HTTP server's threads at once; the device's own lock keeps each call in step
// with the Modbus side.
namespace mblab::web {

struct ApiRequest {
    std::string method;  // GET, POST, PUT, DELETE
    std::string path;    // without the query
    std::map<std::string, std::string> query;
    std::string body;
};

struct ApiReply {
    int status = 200;
    std::string body;  // JSON, one line
};

// How a write of values went: made (and kept, when the server keeps writes), refused whole
// (an address the profile does not map), or made but not kept (the journal could not).
enum class ValueWrite : std::uint8_t { Written, Unmapped, NotDurable };
using WriteValues =
    std::function<ValueWrite(std::uint8_t unit, device::BankKind kind, std::uint32_t start,
                             std::span<const std::uint16_t> values)>;

// What the API sees of the server besides the device.
struct ServeView {
    device::ReferenceDevice& device;
    RequestMeter& meter;
    std::function<std::uint64_t()> connections;  // Modbus/TCP connections open now
    // Saves --state now; empty when serve runs without --state. Returns the file or an error.
    std::function<bool(std::string& file_or_error)> save_state;
    // Writes values the way the server keeps them (`serve --durable` journals them before the
    // answer); empty: straight to the device.
    WriteValues write_values = {};
    // The requests and answers of late (GET /api/traffic); null: none are kept.
    const server::TrafficLog* traffic = nullptr;
};

class DeviceApi {
  public:
    explicit DeviceApi(ServeView view);

    ApiReply handle(const ApiRequest& request);
    const ServeView& view() const { return view_; }

    // The counters of /api/counters, and the values of one page of a bank when `page` names
    // one (unit, bank, start, count as GET /api/units/{unit}/{bank} takes them): what one
    // server-sent event carries to the dashboard.
    nlohmann::json live_event(const std::map<std::string, std::string>& page);

  private:
    struct Rule {
        device::FaultSpec spec;
        bool enabled = true;
    };

    ApiReply units() const;
    ApiReply read_values(std::uint8_t unit, device::BankKind kind,
                         const std::map<std::string, std::string>& query) const;
    ApiReply write_values(std::uint8_t unit, device::BankKind kind, const std::string& address,
                          const std::string& body);
    ApiReply list_rules(std::uint8_t unit);
    ApiReply change_rules(const ApiRequest& request, std::uint8_t unit,
                          const std::vector<std::string>& parts);
    nlohmann::json counters() const;
    ApiReply reset_counters();
    ApiReply save_state();
    ApiReply traffic(const std::map<std::string, std::string>& query) const;
    // Gives the device the enabled rules of `unit`, in order.
    void apply_rules(std::uint8_t unit);

    ServeView view_;
    std::mutex rules_mutex_;
    std::map<std::uint8_t, std::vector<Rule>> rules_;
};

ApiReply api_error(int status, const std::string& reason);

}  // namespace mblab::web
