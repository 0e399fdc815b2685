#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "device/reference_device.hpp"
#include "server/traffic_log.hpp"
#include "web/device_api.hpp"
#include "web/http_server.hpp"
#include "web/request_meter.hpp"

// `mblab serve --http ADDR`: the device's dashboard, REST API and metrics beside the Modbus
// server (docs/http.md).
namespace mblab::cli {

struct HttpOptions {
    std::string address;  // empty: no HTTP
    std::string token;
    std::string token_file;
    bool no_token = false;
    std::vector<std::string> allowed_hosts;
};

void add_http_options(CLI::App& command, HttpOptions& options);

// The checked options: where to listen, the token changes need (empty only with
// --http-no-token on loopback; made at random when none is given) and the host names taken.
struct HttpPlan {
    web::HttpAddress address;
    std::string token;
    std::vector<std::string> names;
    bool token_made = false;
};
// nullopt with an empty `error` when --http is not given.
std::optional<HttpPlan> plan_http(const HttpOptions& options, std::string& error);

// The device as the HTTP side sees it: every request counted on its way to `handler`.
class LiveDevice {
  public:
    LiveDevice(device::ReferenceDevice& device, device::RequestHandler& handler)
        : device_(device), metered_(handler, meter_) {}

    device::RequestHandler& handler() { return metered_; }
    // How REST writes are made (ServeView::write_values); set before start().
    void write_values_with(web::WriteValues write) { write_values_ = std::move(write); }
    // The requests and answers the dashboard shows; set before start().
    void show_traffic(const server::TrafficLog* traffic) { traffic_ = traffic; }

    // Starts the HTTP server and prints where it listens; false with `error` when it cannot.
    bool start(const HttpPlan& plan, std::function<std::uint64_t()> connections,
               std::function<bool(std::string&)> save_state, std::string& error);
    // Ends the HTTP side before what its callbacks look at (the servers) goes.
    void stop() {
        if (server_) server_->stop();
    }

  private:
    device::ReferenceDevice& device_;
    web::RequestMeter meter_;
    web::MeteredHandler metered_;
    web::WriteValues write_values_;
    const server::TrafficLog* traffic_ = nullptr;
    std::unique_ptr<web::DeviceApi> api_;
    std::unique_ptr<web::HttpServer> server_;
};

}  // namespace mblab::cli
