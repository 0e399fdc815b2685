#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "device/reference_device.hpp"
#include "support/device_profiles.hpp"
#include "support/hex.hpp"
#include "web/device_api.hpp"
#include "web/request_meter.hpp"

// A device from a small profile behind the HTTP API and the request meter, asked over Modbus
// (PDU hex in, hex out) and over the API (JSON in, status and JSON out).
namespace mblab::test {

constexpr std::string_view kWebProfile = R"(
[[unit]]
id = 1
holding_registers = [{start = 0, count = 100}, {start = 200, count = 10}]
coils = [{start = 0, count = 16}]
input_registers = [{start = 0, count = 10}]
faults = [{action = "exception", exception = 6, functions = [6]}]
[[unit]]
id = 2
holding_registers = [{start = 0, count = 10}]
)";

class WebHarness {
  public:
    explicit WebHarness(std::string_view profile = kWebProfile)
        : device_(device_from(profile)),
          metered_(*device_, meter_),
          api_(web::ServeView{*device_, meter_, [] { return std::uint64_t{3}; }, {}}) {}

    // A request PDU to `unit` over Modbus/TCP; the answer PDU ("" when none).
    std::string ask(std::string_view pdu, std::uint8_t unit = 1) {
        std::array<std::uint8_t, 260> response{};
        const auto request = hex(pdu);
        const auto reply = metered_.handle({unit, device::Link::Tcp}, request, response);
        if (reply.action != device::ReplyAction::Answer) return "";
        return to_hex(std::span(response).first(reply.size));
    }

    web::ApiReply call(const std::string& method, const std::string& path,
                       const std::string& body = "",
                       std::map<std::string, std::string> query = {}) {
        return api_.handle({method, path, std::move(query), body});
    }
    nlohmann::json json(const web::ApiReply& reply) {
        return nlohmann::json::parse(reply.body, nullptr, false);
    }

    device::ReferenceDevice& device() { return *device_; }
    web::RequestMeter& meter() { return meter_; }
    web::DeviceApi& api() { return api_; }

  private:
    std::unique_ptr<device::ReferenceDevice> device_;
    web::RequestMeter meter_;
    web::MeteredHandler metered_;
    web::DeviceApi api_;
};

}  // namespace mblab::test
